// quiver.simulate(): Python agents (AgentBase subclasses) and checks run in Quiver's simulator from
// a scenario (a dict or a file: the simulator's schema, sim/scenario.h), with partitions, loss,
// kill -9 and restarts, in virtual time; the same agent classes run_agent() runs over DDS.

#include <nlohmann/json.hpp>

#include "action_forward.h"
#include "agent_run.h"
#include "quiver/sim/scenario.h"
#include "quiver/sim/scenario_run.h"

namespace quiver::python {
namespace {

// The simulator's agent for a Python AgentBase: it keeps the Python object alive, forwards the
// agent's calls to it, and takes over the subscriptions and actions it declares.
class HostedAgent final : public agents::Agent {
 public:
  explicit HostedAgent(py::object obj)
      : Agent(obj.cast<agents::Agent&>().name()), obj_(new py::object(std::move(obj))), inner_(obj_->cast<agents::Agent*>()) {
    if (!inner_->grammar_text().empty()) set_grammar_text(inner_->grammar_text(), inner_->grammar_source());
    else if (!inner_->grammar_file().empty()) set_grammar_file(inner_->grammar_file());
    for (const auto& pg : inner_->peer_grammars()) add_peer_grammar(pg.agent, pg.text, pg.source);
    take_over();
  }
  ~HostedAgent() override {
    if (!Py_IsInitialized()) return;
    py::gil_scoped_acquire gil;
    delete obj_;
  }
  void setup(agents::AgentContext& ctx) override {
    inner_->setup(ctx);
    take_over();
  }
  void on_tick(agents::AgentContext& ctx) override { inner_->on_tick(ctx); }
  void teardown(agents::AgentContext& ctx) override { inner_->teardown(ctx); }

 private:
  // What the Python agent declared (in its constructor or setup()) becomes this agent's.
  void take_over() {
    for (auto& s : inner_->subscriptions()) subscribe(std::move(s.filter), std::move(s.fn));
    inner_->subscriptions().clear();
    for (auto& a : inner_->actions()) add_action(std::move(a.action), std::move(a.interest));
    inner_->actions().clear();
  }
  py::object* obj_;
  agents::Agent* inner_;
};

// What a Python check sees of a run: the agents by name, their replicas, the time.
struct SimView {
  sim::ScenarioRun* run = nullptr;
  std::shared_ptr<CallScope> scope;
};

// A Python check: fn(run, params) at the end of the run, returning a list of failures.
class PyCheck final : public sim::Check {
 public:
  PyCheck(std::shared_ptr<PyCallback> fn, nlohmann::json params, std::shared_ptr<CallScope> scope)
      : fn_(std::move(fn)), params_(std::move(params)), scope_(std::move(scope)) {}
  void finish(sim::ScenarioRun& run, std::vector<std::string>& failures) override {
    py::gil_scoped_acquire gil;
    try {
      py::object params = py::module_::import("json").attr("loads")(params_.dump());
      py::object out = fn_->fn()(SimView{&run, scope_}, params);
      if (out.is_none()) return;
      for (py::handle f : out) failures.push_back(py::str(f).cast<std::string>());
    } catch (py::error_already_set& e) {
      failures.push_back("a check raised " + std::string(py::repr(e.value()).cast<std::string>()));
    }
  }

 private:
  std::shared_ptr<PyCallback> fn_;
  nlohmann::json params_;
  std::shared_ptr<CallScope> scope_;
};

GraphHandle graph_of(const SimView& v, int i) {
  GraphHandle h;
  graph::Graph* g = v.run->host().graph(i);
  h.graph = std::shared_ptr<graph::Graph>(std::shared_ptr<void>(), g);  // not owned
  h.owner.scope = v.scope;
  return h;
}

}  // namespace

void bind_sim(py::module_& m) {
  py::class_<SimView>(m, "SimRun", "A simulated run as a check sees it at its end.")
      .def_property_readonly("names", [](const SimView& v) {
        std::vector<std::string> out;
        for (int i = 0; i < v.run->host().size(); ++i) out.push_back(v.run->host().name(i));
        return out;
      }, "The agents' names.")
      .def("up", [](const SimView& v, const std::string& name) {
        const int i = v.run->host().index(name);
        return i >= 0 && v.run->host().up(i);
      }, py::arg("name"), "Whether agent `name` runs now.")
      .def("graph", [](const SimView& v, const std::string& name) -> py::object {
        const int i = v.run->host().index(name);
        if (i < 0 || !v.run->host().graph(i)) return py::none();
        return py::cast(graph_of(v, i));
      }, py::arg("name"), "Agent `name`'s replica (None while it is down); valid during the check.")
      .def_property_readonly("now", [](const SimView& v) { return static_cast<double>(v.run->host().now()) / 1e9; },
                             "Virtual seconds since the start.");

  m.def(
      "simulate",
      [](py::object scenario, py::dict roles, py::dict checks, std::uint64_t seed, py::object log) {
        if (current_run() != nullptr)
          raise(make_error(ErrorCode::kInvalidArgument, "simulate(): this thread already runs an agent"));
        sim::ScenarioApp app("python");
        std::vector<std::string> defaults;
        for (auto [k, v] : roles) {
          const std::string role = py::str(k);
          defaults.push_back(role);
          auto make = std::make_shared<PyCallback>(py::reinterpret_borrow<py::function>(v));
          app.role(role, [make, role](sim::ScenarioRun& run) -> std::unique_ptr<agents::Agent> {
            py::gil_scoped_acquire gil;
            py::object obj;
            try {
              obj = make->fn()(run.agent_name());
            } catch (py::error_already_set& e) {
              keep_run_error(e);
              return nullptr;
            }
            if (!py::isinstance<agents::Agent>(obj)) {
              PyErr_SetString(PyExc_TypeError, ("simulate(): the factory of role '" + role +
                                                "' must return a quiver.AgentBase")
                                                   .c_str());
              py::error_already_set e;
              keep_run_error(e);
              return nullptr;
            }
            return std::make_unique<HostedAgent>(std::move(obj));
          });
        }
        app.default_agents(defaults);
        AgentRun run;
        for (auto [k, v] : checks) {
          auto fn = std::make_shared<PyCallback>(py::reinterpret_borrow<py::function>(v));
          app.check(py::str(k), [fn, scope = run.scope](const nlohmann::json& p, const std::string&)
                                    -> Result<std::unique_ptr<sim::Check>> {
            return std::unique_ptr<sim::Check>(std::make_unique<PyCheck>(fn, p, scope));
          });
        }
        Result<sim::Scenario> s = make_error(ErrorCode::kInvalidArgument, "");
        if (py::isinstance<py::str>(scenario)) {
          s = sim::Scenario::load(scenario.cast<std::string>(), app);
        } else {
          nlohmann::json j;
          try {
            j = nlohmann::json::parse(py::module_::import("json").attr("dumps")(scenario).cast<std::string>());
          } catch (const nlohmann::json::exception& e) {
            raise(make_error(ErrorCode::kInvalidArgument, std::string("simulate(): the scenario: ") + e.what()));
          }
          s = sim::Scenario::parse(j, "scenario", app);
        }
        check(s.ok() ? Status{} : Status(s.error()));
        std::function<void(std::int64_t, const std::string&)> logger;
        std::shared_ptr<PyCallback> log_fn;
        if (!log.is_none()) {
          log_fn = std::make_shared<PyCallback>(log.cast<py::function>());
          logger = [log_fn](std::int64_t t, const std::string& line) {
            guarded([&] { log_fn->fn()(static_cast<double>(t) / 1e9, line); }, /*cleanup=*/true);
          };
        }
        const sim::ScenarioOutcome out =
            run_bound(run, [&] { return sim::run_scenario(*s, app, seed, logger); });
        return py::module_::import("json").attr("loads")(out.to_json().dump());
      },
      py::arg("scenario"), py::arg("roles"), py::kw_only(), py::arg("checks") = py::dict(), py::arg("seed") = 1,
      py::arg("log") = py::none(),
      "Runs a scenario in the simulator with agents written in Python: `scenario` is a dict or the "
      "path of a scenario file (docs/simulation.md: agents by role, faults, checks by name, limit_s); "
      "`roles` maps a role to a factory, factory(name) -> an AgentBase (called again after every "
      "restart); `checks` maps a check's name to fn(run: SimRun, params) -> list of failures, called "
      "at the end. Virtual time; one seed replays a run exactly. Returns the outcome: {'passed', "
      "'failures', 'kills', 'partitions', 'rejected', 'seconds', 'seed', 'name'}. Raises the first "
      "exception an agent's callback raised.");
}

}  // namespace quiver::python
