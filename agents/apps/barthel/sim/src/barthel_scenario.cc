// The Barthel scenario as tests and the CLI state it, run through the simulator's scenario runner.
#include "quiver/agents/apps/barthel/sim/barthel_scenario.h"

#include <nlohmann/json.hpp>

#include "barthel_settings.h"
#include "quiver/base/rng.h"
#include "quiver/sim/fault_generator.h"
#include "quiver/sim/scenario.h"
#include "quiver/sim/scenario_run.h"

namespace quiver::agents::inline apps::barthel {
namespace {

using nlohmann::json;

// The generic scenario of a typed one: its checks stated explicitly (the defaults included).
sim::Scenario generic(const BarthelScenario& s) {
  sim::Scenario g;
  g.name = s.name;
  g.app = "barthel";
  for (const auto& a : s.agents) g.agents.push_back({a, a});
  g.world_file = s.world_file;
  g.faults = s.faults;
  g.settings = internal::write_settings(s.script, s.timing);
  g.checks = {{"result_stored", true},
              {"never_speaking_absent_ms", s.checks.never_speaking_absent_ms},
              {"no_item_asked_twice", s.checks.no_item_asked_twice},
              {"result_matches_script", s.checks.result_matches_script}};
  if (s.checks.status) g.checks["status"] = *s.checks.status;
  if (s.checks.total) g.checks["total"] = *s.checks.total;
  g.limit_s = s.limit_s;
  return g;
}

}  // namespace

Result<BarthelScenario> BarthelScenario::parse(const json& j, const std::string& source) {
  auto g = sim::Scenario::parse(j, source, barthel_app());
  if (!g.ok()) return g.error();
  BarthelScenario s;
  s.name = g->name == "scenario" && !j.contains("name") ? s.name : g->name;
  if (!g->agents.empty()) {
    s.agents.clear();
    for (const auto& a : g->agents) s.agents.push_back(a.name);
  }
  s.world_file = g->world_file;
  s.faults = g->faults;
  if (Status st = internal::read_settings(g->settings, source, s.script, s.timing); !st.ok()) return st.error();
  const json& c = g->checks;
  if (c.contains("never_speaking_absent_ms")) s.checks.never_speaking_absent_ms = c["never_speaking_absent_ms"].get<std::int64_t>();
  if (c.contains("no_item_asked_twice")) s.checks.no_item_asked_twice = c["no_item_asked_twice"].get<bool>();
  if (c.contains("result_matches_script")) s.checks.result_matches_script = c["result_matches_script"].get<bool>();
  if (c.contains("status")) s.checks.status = c["status"].get<std::string>();
  if (c.contains("total")) s.checks.total = c["total"].get<int>();
  s.limit_s = g->limit_s;
  return s;
}

Result<BarthelScenario> BarthelScenario::load(const std::string& path) {
  auto g = sim::Scenario::load(path, barthel_app());
  if (!g.ok()) return g.error();
  return parse(g->to_json(), path);
}

json BarthelScenario::to_json() const { return generic(*this).to_json(); }

BarthelScenario BarthelScenario::random_faults(std::uint64_t seed) {
  Rng rng(seed ^ 0x5ca1ab1e);
  BarthelScenario s;
  s.name = "barthel-faults";
  s.script = PatientScript::varied(seed);
  s.script.think_min_ns = 150'000'000;
  s.script.think_max_ns = 700'000'000;
  for (auto& l : s.script.leaves) {
    l.after_ns = 100'000'000 + static_cast<std::int64_t>(rng.below(500'000'000));
    l.for_ns = 500'000'000 + static_cast<std::int64_t>(rng.below(2'000'000'000));
  }
  s.timing.words_ms = 40;
  s.timing.base_ms = 100;
  s.timing.answer_timeout_s = 3;
  s.timing.person_hz = 20;
  s.timing.joints = false;
  s.limit_s = 600;
  sim::FaultMix mix;
  mix.agents = s.agents;
  mix.killable = {"planner", "speech", "panel", "person"};
  mix.loss_chance = 0.6;
  mix.max_loss = 0.3;
  mix.partition_at = {2, 40};
  mix.kill_at = {1, 40};
  s.faults = sim::random_faults(rng, mix);
  return s;
}

json BarthelResult::to_json() const {
  return {{"name", name},
          {"seed", seed},
          {"passed", passed},
          {"failures", failures},
          {"status", status},
          {"total", total},
          {"expected_status", expected_status},
          {"expected_total", expected_total},
          {"finished_s", finished_s},
          {"max_speaking_absent_ms", max_speaking_absent_ms},
          {"interruptions", interruptions},
          {"kills", kills},
          {"partitions", partitions},
          {"rejected", rejected}};
}

BarthelResult run_scenario(const BarthelScenario& s, std::uint64_t seed,
                           std::function<void(std::int64_t, const std::string&)> log) {
  const sim::Scenario g = generic(s);
  const sim::ScenarioOutcome o = sim::run_scenario(g, barthel_app(), seed, std::move(log));
  BarthelResult r;
  r.name = o.name;
  r.seed = seed;
  r.passed = o.passed;
  r.failures = o.failures;
  const json& m = o.metrics;
  r.status = m.value("status", "");
  r.total = m.value("total", -1);
  r.expected_status = m.value("expected_status", "");
  r.expected_total = m.value("expected_total", -1);
  r.finished_s = m.value("finished_s", -1.0);
  r.max_speaking_absent_ms = m.value("max_speaking_absent_ms", 0.0);
  r.interruptions = m.value("interruptions", 0);
  r.kills = m.value("kills", 0);
  r.partitions = m.value("partitions", 0);
  r.rejected = m.value("rejected", std::uint64_t{0});
  return r;
}

}  // namespace quiver::agents::inline apps::barthel
