// The Python module `quiver`: one binder per concept.

#include "common.h"

PYBIND11_MODULE(quiver, m) {
  using namespace quiver::python;
  m.doc() = "Quiver: a replicated world-model graph (nodes, edges, attributes, an RT tree) over Cyclone DDS";
  m.attr("__version__") = QUIVER_VERSION;
  py::module_::import("numpy");
  bind_errors(m);
  bind_values(m);
  bind_ids(m);
  bind_graph(m);
  bind_transaction(m);
  bind_kinematics(m);
  bind_grammar(m);
  bind_locks(m);
  bind_agent(m);
  bind_agent_context(m);
  bind_action(m);
  bind_agent_base(m);
  bind_bench(m);
  bind_sim(m);
  bind_dsr_facade(m);
}
