// The AGM scenario as tests and the CLI state it, run through the simulator's scenario runner
// with agm_app().
#include "quiver/agents/apps/agm/sim/agm_scenario.h"

#include <nlohmann/json.hpp>

#include "agm_run.h"
#include "quiver/base/rng.h"
#include "quiver/sim/fault_generator.h"
#include "quiver/sim/scenario.h"
#include "quiver/sim/scenario_run.h"

namespace quiver::agents::inline apps::agm {
namespace {

using nlohmann::json;

Error bad(const std::string& source, const std::string& pointer, const std::string& what) {
  return Error{ErrorCode::kInvalidArgument, source + ":" + pointer + ": " + what};
}

// The generic scenario of a typed one: every check, with its parameters; its agents and world
// follow from its settings.
sim::Scenario generic(const AgmScenario& s) {
  sim::Scenario g;
  g.name = s.name;
  g.app = "agm";
  g.faults = s.faults;
  g.settings = internal::write_settings(s);
  g.checks = internal::write_checks(s.checks);
  g.limit_s = s.limit_s;
  return g;
}

}  // namespace

json AgmResult::to_json() const {
  return {{"name", name},
          {"seed", seed},
          {"passed", passed},
          {"failures", failures},
          {"converged", converged},
          {"final_room", final_room},
          {"room_changes", room_changes},
          {"expected_room_changes", expected_room_changes},
          {"reach_changes", reach_changes},
          {"pauses", pauses},
          {"grasps", grasps},
          {"grasped_s", grasped_s},
          {"finished_s", finished_s},
          {"kills", kills},
          {"partitions", partitions},
          {"rejected", rejected},
          {"human_deliveries", human_deliveries},
          {"human_latency_p99_ms", human_latency_p99_ms},
          {"mission_holds", mission_holds},
          {"plan_status", plan_status},
          {"plan_verified", plan_verified},
          {"plan_steps", plan_steps},
          {"plan_version", plan_version},
          {"replans", replans},
          {"releases", releases}};
}

Result<AgmScenario> AgmScenario::parse(const json& j, const std::string& source) {
  auto g = sim::Scenario::parse(j, source, agm_app());
  if (!g.ok()) return g.error();
  for (const char* k : {"agents", "world"})
    if (j.contains(k))
      return bad(source, std::string("/") + k,
                 "an AGM scenario's mission chooses its agents and world");
  AgmScenario s;
  if (j.contains("name")) s.name = g->name;
  s.faults = g->faults;
  if (Status st = internal::read_settings(g->settings, source, s); !st.ok()) return st.error();
  internal::read_check_params(g->checks, s.checks);
  if (j.contains("limit_s")) {
    if (g->limit_s < 45) return bad(source, "/limit_s", "expected a number in [45, 86400]");
    s.limit_s = g->limit_s;
  }
  return s;
}

Result<AgmScenario> AgmScenario::load(const std::string& path) {
  auto j = sim::Scenario::read(path);
  if (!j.ok()) return j.error();
  return parse(*j, path);
}

AgmScenario AgmScenario::random_faults(std::uint64_t seed) { return random_faults(seed, ""); }

AgmScenario AgmScenario::random_faults(std::uint64_t seed, const std::string& mission) {
  Rng rng(seed ^ 0xa6e5ce7a110ULL);
  AgmScenario s;
  s.name = mission.empty() ? "agm-faults" : mission + "-faults";
  s.mission = mission;
  // Under partitions and loss the agents still decide right from what their replicas hold; what
  // they cannot do is see a crossing or a start of motion they are cut off from.
  s.checks.exact_crossings = false;
  s.checks.expect_pause = false;
  s.checks.motion_allowance_ms =
      500;  // the grasping agent's freshness bound (300 ms), ticks, retries
  std::vector<std::string> roles = role_names();
  if (!mission.empty()) roles.push_back(kPlannerRole);
  sim::FaultMix mix;  // loss up to 20%, up to two partitions and two kill -9, all in the first 35 s
  mix.agents = roles;
  mix.killable = roles;
  s.faults = sim::random_faults(rng, mix);
  return s;
}

AgmResult run_agm_scenario(const AgmScenario& s, std::uint64_t seed,
                           std::function<void(std::int64_t, const std::string&)> log) {
  const sim::ScenarioOutcome o = sim::run_scenario(generic(s), agm_app(), seed, std::move(log));
  AgmResult r;
  r.name = o.name;
  r.seed = seed;
  r.passed = o.passed;
  r.failures = o.failures;
  const json& m = o.metrics;
  r.converged = m.value("converged", false);
  r.final_room = m.value("final_room", "");
  r.room_changes = m.value("room_changes", 0);
  r.expected_room_changes = m.value("expected_room_changes", 0);
  r.reach_changes = m.value("reach_changes", 0);
  r.pauses = m.value("pauses", 0);
  r.grasps = m.value("grasps", 0);
  r.releases = m.value("releases", 0);
  r.grasped_s = m.value("grasped_s", -1.0);
  r.finished_s = m.value("finished_s", -1.0);
  r.kills = m.value("kills", 0);
  r.partitions = m.value("partitions", 0);
  r.rejected = m.value("rejected", std::uint64_t{0});
  r.human_deliveries = m.value("human_deliveries", std::uint64_t{0});
  r.human_latency_p99_ms = m.value("human_latency_p99_ms", 0.0);
  r.mission_holds = m.value("mission_holds", false);
  r.plan_status = m.value("plan_status", "");
  r.plan_verified = m.value("plan_verified", "");
  r.plan_steps = m.value("plan_steps", 0);
  r.plan_version = m.value("plan_version", std::int64_t{0});
  r.replans = m.value("replans", std::int64_t{0});
  return r;
}

AgmResult run_agm_clean_table(const AgmScenario& s, std::uint64_t seed,
                              std::function<void(std::int64_t, const std::string&)> log) {
  AgmScenario c = s;
  c.mission = kCleanTable;
  return run_agm_scenario(c, seed, std::move(log));
}

}  // namespace quiver::agents::inline apps::agm
