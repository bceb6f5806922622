// The Barthel test registered with the simulator: roles, settings, checks, shared devices.
#include <memory>
#include <optional>
#include <nlohmann/json.hpp>

#include "barthel_settings.h"
#include "quiver/agents/apps/barthel/barthel_roles.h"
#include "quiver/agents/apps/barthel/checks.h"
#include "quiver/agents/apps/barthel/grammars.h"
#include "quiver/agents/apps/barthel/sim/barthel_scenario.h"
#include "quiver/agents/apps/barthel/speech.h"
#include "quiver/agents/devices/memory_pager.h"
#include "quiver/agents/devices/memory_result_store.h"
#include "quiver/sim/scenario_run.h"

namespace quiver::agents::inline apps::barthel {
namespace {

using nlohmann::json;

// What the agents of one run share: devices that outlive an agent's incarnation (the clinician's
// pager, the result store), the patient's replica as the ground truth, and what is measured.
struct RunState {
  devices::MemoryResultStore store;
  devices::MemoryPager pager;
  RoleOptions roles;
  PatientScript script;
  int patient = -1, speech = -1;
  std::int64_t stored_at = -1;
  AbsenceWatch absence;
  int interruptions = 0;
};

RunState& state(sim::ScenarioRun& run) { return *run.state_as<std::shared_ptr<RunState>>(); }

const graph::Graph* truth(sim::ScenarioRun& run) {
  const int p = state(run).patient;
  return p >= 0 ? run.host().graph(p) : nullptr;
}

Error bad(const std::string& where, const std::string& what) {
  return Error{ErrorCode::kInvalidArgument, where + ": " + what};
}

// A check with a value the stored result must have ("status": "completed", "total": 85).
template <class T, class Fn>
sim::ScenarioApp::CheckFactory value_check(const char* expected, Fn finish) {
  struct C final : sim::Check {
    C(T v, Fn f) : value(std::move(v)), fn(std::move(f)) {}
    T value;
    Fn fn;
    void finish(sim::ScenarioRun& run, std::vector<std::string>& failures) override { fn(run, value, failures); }
  };
  return [expected, finish](const json& p, const std::string& where) -> Result<std::unique_ptr<sim::Check>> {
    if constexpr (std::is_same_v<T, std::string>) {
      if (!p.is_string()) return bad(where, std::string("expected ") + expected);
    } else {
      if (!p.is_number_integer()) return bad(where, std::string("expected ") + expected);
    }
    return std::unique_ptr<sim::Check>(std::make_unique<C>(p.get<T>(), finish));
  };
}

std::optional<devices::TestResult> stored(sim::ScenarioRun& run) { return state(run).store.last(); }

sim::ScenarioApp make_app() {
  sim::ScenarioApp app("barthel");
  app.default_agents(role_names()).default_world(std::string(world_json()));
  for (const std::string& role : role_names())
    app.role(role, [role](sim::ScenarioRun& run) -> std::unique_ptr<Agent> {
      auto a = make_role(role, state(run).roles);
      return a.ok() ? std::move(*a) : nullptr;
    });
  app.settings([](const json& keys, const std::string& source) {
    PatientScript script;
    ScenarioTiming timing;
    return internal::read_settings(keys, source, script, timing);
  });
  app.on_start([](sim::ScenarioRun& run) -> Status {
    auto st = std::make_shared<RunState>();
    ScenarioTiming timing;
    if (Status s = internal::read_settings(run.scenario().settings, run.scenario().name, st->script, timing); !s.ok())
      return s;
    run.state() = st;
    RoleOptions& ro = st->roles;
    ro.truth = [&run]() { return truth(run); };
    ro.script = st->script;
    ro.store = &st->store;
    ro.pager = &st->pager;
    ro.sim_ns_per_word = static_cast<std::int64_t>(timing.words_ms * 1e6);
    ro.sim_base_ns = static_cast<std::int64_t>(timing.base_ms * 1e6);
    ro.planner.answer_timeout_ns = static_cast<std::int64_t>(timing.answer_timeout_s * 1e9);
    ro.planner.needs.clear();
    const auto agents = run.scenario().agents_of(run.app());
    for (const char* n : {"speech", "panel", "person"})
      for (const auto& a : agents)
        if (a.name == n) ro.planner.needs.push_back(n);
    ro.person.rate_hz = timing.person_hz;
    ro.person.joints = timing.joints;
    sim::AgentHost& host = run.host();
    st->patient = host.index("patient");
    st->speech = host.index("speech");
    host.on_action_event([&run](int i, const ActionEvent& e) {
      if (run.host().name(i) == "speech" && e.kind == ActionEvent::Kind::kCancelled) ++state(run).interruptions;
    });
    // Over time: how long the robot spoke to the patient after the person had left.
    host.every(10'000'000, [&run] {
      RunState& s = state(run);
      const graph::Graph* t = truth(run);
      if (!t) return;
      bool speaking = false;
      sim::AgentHost& h = run.host();
      if (s.speech >= 0 && h.up(s.speech) && h.agent(s.speech)) {
        auto* sp = dynamic_cast<Speech*>(h.agent(s.speech));
        speaking = sp && sp->output().playing(h.now()) && speaking_to_patient(*h.graph(s.speech));
      }
      s.absence.sample(h.now(), patient_present_truth(*t), speaking);
      if (s.stored_at < 0 && s.store.last()) s.stored_at = h.now();
    });
    return {};
  });
  // Done once the result is stored and the closing words said.
  app.done_when([](sim::ScenarioRun& run) {
    const RunState& s = state(run);
    return s.stored_at >= 0 && run.host().now() - s.stored_at > 15'000'000'000;
  });
  app.report([](sim::ScenarioRun& run, json& m) {
    RunState& s = state(run);
    const auto expected = s.script.expected();
    m["expected_status"] = expected.status;
    m["expected_total"] = expected.total;
    m["max_speaking_absent_ms"] = s.absence.max_ms();
    m["interruptions"] = s.interruptions;
    const auto r = stored(run);
    m["status"] = r ? r->status : "";
    m["total"] = r ? r->total : -1;
    m["finished_s"] = r ? static_cast<double>(s.stored_at) / 1e9 : -1.0;
  });
  // The checks: a result is stored (always), and what the scenario asks of it.
  app.check("result_stored", sim::switch_check([](sim::ScenarioRun& run, std::vector<std::string>& f) {
    if (!stored(run))
      f.push_back("no result stored within " + std::to_string(run.scenario().limit_s) + " s of virtual time");
  }));
  app.check("never_speaking_absent_ms", [](const json& p, const std::string& where) -> Result<std::unique_ptr<sim::Check>> {
    struct C final : sim::Check {
      std::int64_t limit = 0;
      void finish(sim::ScenarioRun& run, std::vector<std::string>& f) override {
        const double ms = state(run).absence.max_ms();
        if (ms > static_cast<double>(limit))
          f.push_back("spoke to the patient " + std::to_string(ms) + " ms after the person had left (limit " +
                      std::to_string(limit) + " ms)");
      }
    };
    if (!p.is_number_integer()) return bad(where, "expected an integer");
    if (p.get<std::int64_t>() <= 0) return std::unique_ptr<sim::Check>();
    auto c = std::make_unique<C>();
    c->limit = p.get<std::int64_t>();
    return std::unique_ptr<sim::Check>(std::move(c));
  });
  app.check("status", value_check<std::string>("completed or clinician_called",
                                               [](sim::ScenarioRun& run, const std::string& v, std::vector<std::string>& f) {
                                                 if (const auto r = stored(run); r && r->status != v)
                                                   f.push_back("status " + r->status + ", expected " + v);
                                               }));
  app.check("total", value_check<int>("an integer", [](sim::ScenarioRun& run, int v, std::vector<std::string>& f) {
    if (const auto r = stored(run); r && r->total != v)
      f.push_back("total " + std::to_string(r->total) + ", expected " + std::to_string(v));
  }));
  app.check("result_matches_script", sim::switch_check([](sim::ScenarioRun& run, std::vector<std::string>& f) {
    if (const auto r = stored(run))
      for (const auto& d : result_differences(*r, state(run).script.expected())) f.push_back(d);
  }));
  app.check("no_item_asked_twice", sim::switch_check([](sim::ScenarioRun& run, std::vector<std::string>& f) {
    // Read the patient's replica (never killed): every prompt the robot said to the end.
    const graph::Graph* g = truth(run);
    if (!g) f.push_back("no replica to check the questions in");
    else
      for (const auto& d : questions_asked_twice(*g)) f.push_back(d);
  }));
  return app;
}

}  // namespace

const sim::ScenarioApp& barthel_app() {
  static const sim::ScenarioApp app = make_app();
  return app;
}

}  // namespace quiver::agents::inline apps::barthel
