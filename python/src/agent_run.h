#pragma once
// The Python side of one run_agent() call: the context its callbacks see, the first exception
// they raised, and the guard every call into Python from the C++ runtime goes through.

#include <optional>
#include <stdexcept>

#include "common.h"
#include "quiver/agents/runtime/api/agent.h"

namespace quiver::python {

/// One run_agent() call, on the thread that runs it (the runtime calls the agent there).
struct AgentRun {
  std::shared_ptr<CallScope> scope = std::make_shared<CallScope>();
  std::optional<py::error_already_set> error;  ///< the first exception a callback raised
  agents::AgentContext* raw = nullptr;         ///< the context `ctx` wraps
  py::object ctx;                              ///< the quiver.AgentContext given to callbacks
};

/// The run of this thread, or null outside run_agent().
AgentRun* current_run();
/// Makes `r` (or null) this thread's run.
void bind_current_run(AgentRun* r);
/// GIL held, inside a run: the quiver.AgentContext that wraps `ctx`.
py::object context_object(agents::AgentContext& ctx);
/// GIL held: keeps the first exception of the run (printing it) and asks the host to stop.
void keep_run_error(py::error_already_set& e);
bool run_failed();

/// Calls `fn` with the GIL held and keeps what it raises (then returns false). After a callback
/// failed, further calls are skipped (false) unless `cleanup` (cancel(), teardown()).
template <class F>
bool guarded(F&& fn, bool cleanup = false) {
  py::gil_scoped_acquire gil;
  if (!cleanup && run_failed()) return false;
  try {
    fn();
    return true;
  } catch (py::error_already_set& e) {
    keep_run_error(e);
  } catch (const std::exception& e) {
    PyErr_SetString(PyExc_RuntimeError, e.what());
    py::error_already_set err;
    keep_run_error(err);
  }
  return false;
}

/// Runs `host` (a call that runs agents, which call back into Python) with `run` bound to this
/// thread and the GIL released; then closes the run's scope and rethrows the first exception a
/// callback raised. GIL held on entry and on return. @returns what `host` returned.
/// @throws py::error_already_set raised by a callback.
template <class F>
auto run_bound(AgentRun& run, F&& host) {
  decltype(host()) out{};
  {
    struct Unbind {
      ~Unbind() { bind_current_run(nullptr); }
    } unbind;
    bind_current_run(&run);
    py::gil_scoped_release release;
    out = host();
  }
  run.scope->open = false;
  run.ctx = py::none();
  if (run.error) {
    py::error_already_set e = std::move(*run.error);
    run.error.reset();
    throw e;
  }
  return out;
}

}  // namespace quiver::python
