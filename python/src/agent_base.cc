// quiver.AgentBase and quiver.run_agent(): a runtime agent written in Python (setup, on_tick,
// teardown, status; subscriptions and actions) run by the C++ process host over Cyclone DDS, the
// GIL released while it runs and taken for every callback.

#include <csignal>
#include <nlohmann/json.hpp>

#include "action_forward.h"
#include "agent_run.h"
#include "quiver/agents/runtime/process/process_host.h"

namespace quiver::python {
namespace {

using agents::AgentContext;

/// The trampoline: the runtime's calls reach the Python overrides.
class PyAgentBase : public agents::Agent {
 public:
  using agents::Agent::Agent;

  void setup(AgentContext& ctx) override { call("setup", ctx); }
  void on_tick(AgentContext& ctx) override { call("on_tick", ctx); }
  void teardown(AgentContext& ctx) override { call("teardown", ctx, /*cleanup=*/true); }
  void status(nlohmann::json& out) const override {
    if (current_run() == nullptr) return;
    guarded([&] {
      py::function f = py::get_override(static_cast<const agents::Agent*>(this), "status");
      if (!f) return;
      py::object r = f();
      if (r.is_none()) return;
      if (!py::isinstance<py::dict>(r))
        throw py::type_error("AgentBase.status() must return a dict");
      auto j =
          nlohmann::json::parse(py::module_::import("json").attr("dumps")(r).cast<std::string>());
      out.update(j);
    });
  }

 private:
  void call(const char* fn, AgentContext& ctx, bool cleanup = false) {
    guarded(
        [&] {
          if (py::function f = py::get_override(static_cast<const agents::Agent*>(this), fn))
            f(context_object(ctx));
        },
        cleanup);
  }
};

/// AgentBase.call(fn): runs fn on the agent's thread and settles its Future with the result or
/// the exception; a task its host dropped unrun settles it with RuntimeError (C++'s call() leaves
/// broken_promise).
class PostedCall {
 public:
  PostedCall(py::function fn, const py::object& future)
      : fn_(std::move(fn)), set_result_(future.attr("set_result")), set_exception_(future.attr("set_exception")) {}
  PostedCall(const PostedCall&) = delete;
  PostedCall& operator=(const PostedCall&) = delete;
  ~PostedCall() {
    if (ran_ || !Py_IsInitialized()) return;
    py::gil_scoped_acquire gil;
    try {
      set_exception_.fn()(py::module_::import("builtins").attr("RuntimeError")(
          "AgentBase.call(): the agent's host stopped before the task ran"));
    } catch (py::error_already_set&) {
    }
  }
  void run() {
    py::gil_scoped_acquire gil;
    ran_ = true;
    try {
      py::object r = fn_.fn()();
      set_result_.fn()(r);
    } catch (py::error_already_set& e) {
      set_exception_.fn()(e.value());
    }
  }

 private:
  PyCallback fn_, set_result_, set_exception_;
  bool ran_ = false;
};

/// Restores the signal handlers (Python's) that run_process() replaces.
class SignalHandlersKept {
 public:
  SignalHandlersKept() {
    sigaction(SIGINT, nullptr, &int_);
    sigaction(SIGTERM, nullptr, &term_);
  }
  ~SignalHandlersKept() {
    sigaction(SIGINT, &int_, nullptr);
    sigaction(SIGTERM, &term_, nullptr);
  }

 private:
  struct sigaction int_ {
  }, term_{};
};

}  // namespace

void bind_agent_base(py::module_& m) {
  using V = std::vector<std::string>;
  py::class_<agents::Agent, PyAgentBase>(m, "AgentBase",
                                         "A runtime agent written in Python: subclass it, declare "
                                         "subscriptions and actions in setup(ctx), and run "
                                         "it with run_agent(). The same shape as a C++ "
                                         "quiver::agents::Agent: the host calls setup(ctx) once, "
                                         "on_tick(ctx) about every 10 ms, teardown(ctx) when it "
                                         "stops, and status() for its status lines.")
      .def(py::init<std::string>(), py::arg("name"))
      .def_property_readonly("name", &agents::Agent::name)
      .def(
          "setup", [](agents::Agent&, py::object) {}, py::arg("ctx"),
          "Declares subscriptions, actions and timers; called once, with the replica joined to its "
          "peers.")
      .def(
          "on_tick", [](agents::Agent&, py::object) {}, py::arg("ctx"),
          "Called every host tick (about 10 ms).")
      .def(
          "teardown", [](agents::Agent&, py::object) {}, py::arg("ctx"),
          "Called once when the host stops (running actions have been cancelled).")
      .def(
          "status", [](const agents::Agent&) { return py::dict(); },
          "The agent's own fields for the host's JSON status lines (a dict of JSON values).")
      .def("set_grammar_file", &agents::Agent::set_grammar_file, py::arg("path"),
           "Every change this agent commits must be one rule application of this grammar.")
      .def("set_grammar_text", &agents::Agent::set_grammar_text, py::arg("text"),
           py::arg("source") = "grammar",
           "As set_grammar_file(), with the grammar given as text (errors name `source`).")
      .def_property_readonly("grammar_file", &agents::Agent::grammar_file)
      .def_property_readonly("grammar_text", &agents::Agent::grammar_text)
      .def("add_peer_grammar", &agents::Agent::add_peer_grammar, py::arg("agent"), py::arg("text"),
           py::arg("source") = "peer grammar",
           "Verifies the changes of agent `agent` against this grammar.")
      .def(
          "subscribe",
          [](agents::Agent& a, py::function callback, const V& node_types, const V& edge_types,
             const V& attributes) {
            auto holder = std::make_shared<PyCallback>(std::move(callback));
            a.subscribe(to_filter(node_types, edge_types, attributes),
                        [holder](AgentContext& ctx, const graph::ChangeBatch& b) {
                          guarded([&] { holder->fn()(context_object(ctx), b); });
                        });
          },
          py::arg("callback"), py::kw_only(), py::arg("node_types") = V{},
          py::arg("edge_types") = V{}, py::arg("attributes") = V{},
          "Calls callback(ctx, ChangeBatch) with the part of every change (local or merged) the "
          "filter selects "
          "(no filter: everything). In setup() (or before run_agent()).")
      .def(
          "post",
          [](agents::Agent& a, py::function fn) {
            auto holder = std::make_shared<PyCallback>(std::move(fn));
            a.post([holder] { guarded([&] { holder->fn()(); }); });
          },
          py::arg("fn"),
          "From any thread: runs fn() on the agent's thread at the host's next tick (about 10 ms), "
          "where it may read and write the graph (as C++ Agent::post).")
      .def(
          "call",
          [](agents::Agent& a, py::function fn) {
            py::object future = py::module_::import("concurrent.futures").attr("Future")();
            auto task = std::make_shared<PostedCall>(std::move(fn), future);
            a.post([task] { task->run(); });
            return future;
          },
          py::arg("fn"),
          "From any thread but the agent's: as post(), and returns a concurrent.futures.Future of "
          "fn()'s result (or of what it raised).")
      .def(
          "add_action",
          [](agents::Agent& a, py::object action, const V& node_types, const V& edge_types,
             const V& attributes) {
            if (!py::isinstance<agents::Action>(action))
              throw py::type_error("add_action(): a quiver.Action is needed");
            a.add_action(std::make_unique<ForwardingAction>(std::move(action)),
                         to_filter(node_types, edge_types, attributes));
          },
          py::arg("action"), py::kw_only(), py::arg("node_types") = V{},
          py::arg("edge_types") = V{}, py::arg("attributes") = V{},
          "Adds an action (evaluated in the order added). The filter narrows which changes make "
          "the runtime "
          "call its find() again (ticks and timers always do).");

  m.def("request_stop", &agents::request_stop,
        "Makes the running run_agent() stop as if SIGTERM had arrived (running actions cancelled, teardown() "
        "called). Thread-safe; a call before run_agent() starts is forgotten.");
  m.def(
      "run_agent",
      [](agents::Agent& agent, std::uint32_t domain, const std::string& dds_config,
         std::optional<std::string> world, std::optional<std::string> world_text, double run_for,
         std::uint64_t seed, int status_ms, double join_wait, int loss_permille, double hang, bool final_status,
         std::optional<std::string> schema, double lease, double hand_over, std::optional<std::string> store,
         const std::string& durability, double store_compact_mb, std::optional<std::string> security,
         const std::string& membership) {
        if (current_run() != nullptr)
          raise(make_error(ErrorCode::kInvalidArgument,
                           "run_agent(): this thread already runs an agent"));
        agents::ProcessFlags f;
        f.domain = domain;
        f.dds_config = dds_config;
        if (world) f.world = *world;
        if (world_text) f.world_text = *world_text;
        f.run_for_s = run_for;
        f.seed = seed;
        f.status_ms = status_ms;
        f.final_status = final_status;
        f.join_wait_s = join_wait;
        f.loss_permille = loss_permille;
        f.hang_s = hang;
        if (schema) f.schema = *schema;
        f.lease_s = lease;
        f.hand_over_s = hand_over;
        if (store) f.store = *store;
        f.durability = durability;
        f.store_compact_mb = store_compact_mb;
        if (security) f.security = *security;
        f.membership = membership;
        if (domain > 230)
          raise(make_error(ErrorCode::kInvalidArgument,
                           "run_agent(): domain " + std::to_string(domain) + " is above 230"));
        if (run_for < 0 || join_wait < 0 || hang < 0)
          raise(make_error(ErrorCode::kInvalidArgument,
                           "run_agent(): negative run_for, join_wait or hang"));
        AgentRun run;
        Error why;
        const int rc = run_bound(run, [&] {
          SignalHandlersKept handlers;
          return agents::run_process(agent, f, &why);
        });
        if (rc != 0)
          raise(make_error(why.code, "run_agent(): agent '" + agent.name() + "' could not start: " + why.message));
        return rc;
      },
      py::arg("agent"), py::kw_only(), py::arg("domain") = 0, py::arg("dds_config") = "loopback",
      py::arg("world") = py::none(), py::arg("world_text") = py::none(), py::arg("run_for") = 0.0,
      py::arg("seed") = 1, py::arg("status_ms") = 0, py::arg("join_wait") = 1.5,
      py::arg("loss_permille") = 0, py::arg("hang") = 1.0, py::arg("final_status") = true,
      py::arg("schema") = py::none(), py::arg("lease") = 1.0, py::arg("hand_over") = 2.0,
      py::arg("store") = py::none(), py::arg("durability") = "batch", py::arg("store_compact_mb") = 64.0,
      py::arg("security") = py::none(), py::arg("membership") = "gossip",
      "Runs `agent` (an AgentBase) as this process's agent over Cyclone DDS until SIGINT/SIGTERM, "
      "or `run_for` "
      "seconds (0: until a signal). The GIL is released meanwhile and taken for every callback. A "
      "callback that blocks keeps the agent alive for its peers (its heartbeats go on, its locks "
      "hold); one running longer than `hang` seconds (0: never) is reported once in the log; long "
      "work belongs in ctx.run_job(work, done). A "
      "world file "
      "`world` (or `world_text`) seeds the shared graph. Prints a JSON status line on stdout every "
      "`status_ms` "
      "and one at the end (final_status=False: none at the end). `schema`: the shared vocabulary file "
      "every agent of the domain loads (docs/schema.md). `lease`, `hand_over`, `store`, `durability`, "
      "`store_compact_mb`, `security` and `membership` are the agent process's --lease, --hand-over, --store, "
      "--durability, --store-compact-mb, --security and --membership (docs/agents.md). Raises the first exception a callback raised (which stops the agent), "
      "or "
      "quiver.Error if the agent could not start. Meant for a dedicated process: SIGINT/SIGTERM "
      "stop the agent "
      "(Python's handlers are back when it returns). Network safety: dds_config='loopback' (the "
      "default) binds "
      "127.0.0.1 with multicast off.");
}

}  // namespace quiver::python
