// quiver.Action: one turn of the DSR loop, subclassed in Python (find -> lock -> start ->
// process -> finish, or cancel), with quiver.Match, quiver.Progress and quiver.CancelReason.

#include "action_forward.h"
#include "agent_run.h"

namespace quiver::python {
namespace {

using agents::AgentContext;
using agents::CancelReason;
using agents::Match;
using agents::Progress;

/// The trampoline: every virtual calls the Python override (GIL taken, exceptions kept by the run).
class PyAction : public agents::Action {
 public:
  using agents::Action::Action;

  std::vector<Match> find(AgentContext& ctx) override {
    std::vector<Match> out;
    guarded([&] {
      py::function f = override("find");
      if (!f) throw std::logic_error("Action '" + name() + "': find(ctx) is not overridden");
      py::object r = f(context_object(ctx));
      if (!r.is_none()) out = r.cast<std::vector<Match>>();
    });
    return out;
  }

  bool holds(AgentContext& ctx, const Match& m) override {
    bool ok = true;
    bool ran = guarded([&] {
      if (py::function f = override("holds")) ok = py::bool_(f(context_object(ctx), m));
    });
    return ran && ok;
  }

  std::optional<agents::LockNeed> lock(AgentContext& ctx, const Match& m) override {
    std::optional<agents::LockNeed> need;
    guarded([&] {
      py::function f = override("lock");
      if (!f) return;
      py::object r = f(context_object(ctx), m);
      if (r.is_none()) return;
      agents::LockNeed n;
      if (py::isinstance<py::tuple>(r)) {
        auto t = r.cast<py::tuple>();
        if (t.size() != 2)
          throw py::value_error("Action.lock(): return None, a root, or (root, priority)");
        n.root = to_node(ctx.graph(), t[0]);
        n.priority = t[1].cast<std::int64_t>();
      } else {
        n.root = to_node(ctx.graph(), r);
      }
      need = n;
    });
    return need;
  }

  Status start(AgentContext& ctx, const Match& m) override { return verdict("start", ctx, m); }

  Progress process(AgentContext& ctx, const Match& m) override {
    Progress p = Progress::kDone;
    bool ran = guarded([&] {
      py::function f = override("process");
      if (!f) return;
      py::object r = f(context_object(ctx), m);
      if (!r.is_none()) p = r.cast<Progress>();
    });
    return ran ? p : Progress::kFailed;
  }

  Status finish(AgentContext& ctx, const Match& m) override { return verdict("finish", ctx, m); }

  void cancel(AgentContext& ctx, const Match& m, CancelReason why) override {
    guarded(
        [&] {
          if (py::function f = override("cancel")) f(context_object(ctx), m, why);
        },
        /*cleanup=*/true);
  }

 private:
  py::function override(const char* fn) const {
    return py::get_override(static_cast<const agents::Action*>(this), fn);
  }

  /// start()/finish(): None or True is success; False or a string refuses (the string says why).
  Status verdict(const char* fn, AgentContext& ctx, const Match& m) {
    Status s;
    bool ran = guarded([&] {
      py::function f = override(fn);
      if (!f) return;
      py::object r = f(context_object(ctx), m);
      if (r.is_none() || (py::isinstance<py::bool_>(r) && r.cast<bool>())) return;
      std::string why = py::isinstance<py::str>(r) ? r.cast<std::string>() : std::string("refused");
      s = make_error(ErrorCode::kRefused, name() + "." + fn + "(): " + why);
    });
    if (!ran)
      return make_error(ErrorCode::kInternal, name() + "." + fn + "(): raised (see run_agent())");
    return s;
  }
};

}  // namespace

ForwardingAction::ForwardingAction(py::object action)
    : agents::Action(action.cast<agents::Action&>().name()),
      target_(&action.cast<agents::Action&>()),
      keep_(new py::object(std::move(action))) {}

ForwardingAction::~ForwardingAction() {
  if (Py_IsInitialized()) {
    py::gil_scoped_acquire gil;
    delete keep_;
  }
}

void bind_action(py::module_& m) {
  py::enum_<Progress>(m, "Progress", "What Action.process() reports.")
      .value("RUNNING", Progress::kRunning,
             "not done yet: process() is called again on the next tick")
      .value("DONE", Progress::kDone, "finish() comes next")
      .value("FAILED", Progress::kFailed, "cancel() comes next (reason FAILED)");
  py::enum_<CancelReason>(m, "CancelReason", "Why a running action was cancelled.")
      .value("PRECONDITION_GONE", CancelReason::kPreconditionGone, "holds() turned false")
      .value("LOCK_LOST", CancelReason::kLockLost, "another agent took its scope")
      .value("FAILED", CancelReason::kFailed, "process() reported failure (or raised)")
      .value("STOPPING", CancelReason::kStopping, "the agent is stopping");

  py::class_<Match>(
      m, "Match",
      "What an action works on: nodes by role, and a key that tells two runs of one action apart "
      "(an action runs at most once per key at a time).")
      .def(py::init([](std::string key, std::map<std::string, graph::NodeId, std::less<>> nodes) {
             Match x;
             x.key = std::move(key);
             x.nodes = std::move(nodes);
             return x;
           }),
           py::arg("key"), py::arg("nodes") = std::map<std::string, graph::NodeId, std::less<>>{})
      .def_readwrite("key", &Match::key)
      .def_readwrite("nodes", &Match::nodes)
      .def(
          "at",
          [](const Match& x, const std::string& role) -> std::optional<graph::NodeId> {
            auto it = x.nodes.find(role);
            if (it == x.nodes.end()) return std::nullopt;
            return it->second;
          },
          py::arg("role"), "The node of `role`, or None.")
      .def("__repr__", [](const Match& x) { return "<Match " + x.key + ">"; });

  py::class_<agents::Action, PyAction>(m, "Action",
                                       "One turn of the DSR loop, subclassed in Python. The "
                                       "runtime calls find(ctx) after relevant changes; for "
                                       "each new Match it takes lock(ctx, m) if any, calls "
                                       "start(ctx, m) (mark it executing with a graph change), "
                                       "then process(ctx, m) every tick until DONE (then "
                                       "finish(ctx, m) writes the result) or FAILED. While it "
                                       "runs, holds(ctx, m) turning false (or a lost lock) calls "
                                       "cancel(ctx, m, reason). start()/finish() return "
                                       "None (ok), or False / a string to refuse.")
      .def(py::init<std::string>(), py::arg("name"))
      .def_property_readonly("name", &agents::Action::name)
      .def(
          "find",
          [](agents::Action&, py::object) -> py::list {
            throw py::type_error("Action.find(ctx) must be overridden");
          },
          py::arg("ctx"), "Every Match that calls for this action now (a list).")
      .def(
          "holds", [](agents::Action&, py::object, const Match&) { return true; }, py::arg("ctx"),
          py::arg("match"), "While running: does the precondition still hold? (default True)")
      .def(
          "lock", [](agents::Action&, py::object, const Match&) { return py::none(); },
          py::arg("ctx"), py::arg("match"),
          "The lock to hold while it runs: None (default), a root node, or (root, priority).")
      .def(
          "start", [](agents::Action&, py::object, const Match&) { return py::none(); },
          py::arg("ctx"), py::arg("match"),
          "Mark it executing (a graph change). None: started; False or a string: refused (tried "
          "again later).")
      .def(
          "process", [](agents::Action&, py::object, const Match&) { return Progress::kDone; },
          py::arg("ctx"), py::arg("match"),
          "Called every tick while it runs: Progress.RUNNING, DONE or FAILED (default DONE).")
      .def(
          "finish", [](agents::Action&, py::object, const Match&) { return py::none(); },
          py::arg("ctx"), py::arg("match"), "Write the result.")
      .def(
          "cancel", [](agents::Action&, py::object, const Match&, CancelReason) {}, py::arg("ctx"),
          py::arg("match"), py::arg("reason"),
          "Stop it and take its mark back. Called at most once per run.");
}

}  // namespace quiver::python
