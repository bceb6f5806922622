// quiver.dsr: pydsr's names over Quiver (python/quiver_dsr.py, embedded at build time), registered
// as the submodule `quiver.dsr` so that `from quiver.dsr import DSRGraph` works.

#include <pybind11/eval.h>

#include "common.h"
#include "dsr_facade_source.h"

namespace quiver::python {

void bind_dsr_facade(py::module_& m) {
  py::module_ dsr = m.def_submodule("dsr", "pydsr's names (DSRGraph, Node, Edge, Attribute, signals) over Quiver");
  dsr.attr("_q") = m;
  // Compiled under its source file's name, so that tracebacks name it.
  py::module_ builtins = py::module_::import("builtins");
  builtins.attr("exec")(builtins.attr("compile")(kDsrFacadeSource, "python/quiver_dsr.py", "exec"), dsr.attr("__dict__"));
  py::module_::import("sys").attr("modules")["quiver.dsr"] = dsr;
}

}  // namespace quiver::python
