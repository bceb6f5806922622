#pragma once
// Shared pieces of the Python module: error translation, value conversion, the handles that tie
// a graph (or a lock manager, a guard) to the thread that owns it.

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <atomic>
#include <memory>
#include <optional>
#include <string>
#include <thread>

#include "quiver/agents/runtime/engine/callback_watch.h"
#include "quiver/graph/graph.h"
#include "quiver/base/result.h"

namespace quiver::python {

namespace py = pybind11;

// ---- errors (errors.cc) ----

/// Raises the Python exception that matches `e.code` (TypeError, ValueError, KeyError kinds,
/// quiver.RefusedError, ...), with the C++ message.
[[noreturn]] void raise(const Error& e);
inline void check(const Status& s) {
  if (!s.ok()) raise(s.error());
}
template <class T>
T unwrap(Result<T> r) {
  if (!r.ok()) raise(r.error());
  return std::move(r).value();
}

// ---- ownership ----

class AgentCore;

/// A window in which an object lent to Python is valid: while it is open, on one thread (e.g. the
/// AgentContext and graph a runtime agent's callbacks get, valid while run_agent() runs).
struct CallScope {
  std::atomic<bool> open{true};
  std::thread::id thread = std::this_thread::get_id();
};

/// Whose thread may touch an object: any thread (a standalone graph: the GIL serialises calls),
/// or one agent's thread while that agent runs.
struct Owner {
  std::shared_ptr<AgentCore> agent;  ///< null: standalone (or scoped)
  std::shared_ptr<const CallScope> scope;  ///< non-null: valid in this scope only (a runtime agent's graph)
  /// True for a graph some agent owns (a quiver.Agent's or a runtime agent's).
  bool owned() const { return agent != nullptr || scope != nullptr; }
  /// Throws RuntimeError off the agent's thread or after the agent stopped.
  void check(const char* fn) const;
  bool on_owner_thread() const;
};

/// A graph as Python sees it. Copies share the graph.
struct GraphHandle {
  std::shared_ptr<graph::Graph> graph;  ///< owned, or aliasing the agent that owns it
  Owner owner;
  graph::Graph& get(const char* fn) const {
    owner.check(fn);
    return *graph;
  }
};

/// An object that works on a graph (a grammar guard, a lock manager, a frame tree): usable only
/// where the graph itself is.
template <class T>
struct OnGraph {
  GraphHandle h;
  std::unique_ptr<T> obj;
  T& get(const char* fn) {
    h.owner.check(fn);
    return *obj;
  }
  graph::Graph& graph() { return *h.graph; }
};

/// A Python callable kept by C++ (callbacks): dropped with the GIL held, whichever thread lets go.
class PyCallback {
 public:
  explicit PyCallback(py::function fn) : fn_(new py::function(std::move(fn))) {}
  ~PyCallback();
  PyCallback(const PyCallback&) = delete;
  PyCallback& operator=(const PyCallback&) = delete;
  const py::function& fn() const { return *fn_; }

 private:
  py::function* fn_;
};

/// A Python exception a callback raised (GIL held): an agent keeps the first one and raises it
/// from Agent.stop() / Agent.check(); elsewhere it is printed as unraisable.
void report_callback_error(py::error_already_set& e, const std::weak_ptr<AgentCore>& agent);
/// On `agent`'s thread while it runs: marks a call into Python code on its engine's watch (for the
/// keeper that keeps a blocked agent alive and reports it); elsewhere nothing.
std::optional<agents::CallbackWatch::Scope> mark_user_code(const std::weak_ptr<AgentCore>& agent);

/// Wraps a Python callable as a C++ callback that takes the GIL, converts its arguments and
/// reports what it raises.
template <class... Args>
std::function<void(const Args&...)> make_callback(py::function fn, const Owner& owner) {
  auto holder = std::make_shared<PyCallback>(std::move(fn));
  std::weak_ptr<AgentCore> agent = owner.agent;
  return [holder, agent](const Args&... args) {
    auto in = mark_user_code(agent);  // a keeper sees a callback that blocks
    py::gil_scoped_acquire gil;
    try {
      holder->fn()(args...);
    } catch (py::error_already_set& e) {
      report_callback_error(e, agent);
    }
  };
}

// ---- values (values.cc) ----

/// A Python object as a graph value. `existing` (the attribute's current value, if any) sets the
/// type when the object converts to it (an int written to an int32 attribute stays int32).
graph::Value to_value(py::handle obj, const graph::Value* existing = nullptr);
py::object from_value(const graph::Value& v);
graph::Symbol to_symbol(py::handle name);

// ---- ids and poses (ids.cc) ----

/// A node given as a NodeId or by name.
graph::NodeId to_node(const graph::Graph& g, py::handle node);
py::array_t<double> pose_to_matrix(const graph::Pose& p);
graph::Pose matrix_to_pose(py::handle X, const char* fn);

// ---- binders ----
void bind_errors(py::module_& m);
void bind_values(py::module_& m);
void bind_ids(py::module_& m);
void bind_graph(py::module_& m);
void bind_transaction(py::module_& m);
void bind_kinematics(py::module_& m);
void bind_grammar(py::module_& m);
void bind_locks(py::module_& m);
void bind_agent(py::module_& m);
void bind_agent_context(py::module_& m);
void bind_action(py::module_& m);
void bind_agent_base(py::module_& m);
void bind_bench(py::module_& m);
void bind_sim(py::module_& m);
void bind_dsr_facade(py::module_& m);

/// A ChangeFilter from lists of names (empty lists: everything); the subscribe() calls' filter.
graph::ChangeFilter to_filter(const std::vector<std::string>& node_types,
                              const std::vector<std::string>& edge_types,
                              const std::vector<std::string>& attributes);

}  // namespace quiver::python
