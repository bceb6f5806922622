// Running a scenario: its agents on the agent host, its faults, workloads and checks.
#include "quiver/sim/scenario_run.h"

#include <fstream>
#include <sstream>

#include "quiver/sim/simulator.h"

namespace quiver::sim {

nlohmann::json ScenarioOutcome::to_json() const {
  nlohmann::json j = metrics;
  j["name"] = name;
  j["seed"] = seed;
  j["passed"] = passed;
  j["failures"] = failures;
  return j;
}

ScenarioRun::ScenarioRun(const Scenario& s, const ScenarioApp& app, std::uint64_t seed,
                         std::function<void(std::int64_t, const std::string&)> log)
    : s_(s), app_(app), seed_(seed), log_(std::move(log)) {}

void ScenarioRun::note(const std::string& line) {
  if (log_) log_(host_ ? host_->now() : 0, line);
}

ScenarioOutcome ScenarioRun::run() {
  ScenarioOutcome out;
  out.name = s_.name;
  out.seed = seed_;
  auto fail = [&](const std::string& f) {
    if (out.failures.size() < 20) out.failures.push_back(f);
  };
  std::string world = app_.default_world(s_.settings);
  if (!s_.world_file.empty()) {
    std::ifstream in(s_.world_file);
    if (!in) {
      fail(s_.world_file + ": cannot open the world file");
      return out;
    }
    std::stringstream ss;
    ss << in.rdbuf();
    world = ss.str();
  }
  std::vector<SimAgentSpec> specs;
  for (const ScenarioAgent& a : s_.agents_of(app_)) {
    if (!app_.has_role(a.role)) {
      fail("no role '" + a.role + "' in the app '" + app_.name() + "'");
      return out;
    }
    specs.push_back({a.name, [this, role = a.role, name = a.name]() {
                       making_ = name;
                       auto agent = app_.role_factory(role)(*this);
                       making_.clear();
                       return agent;
                     }});
  }
  AgentHostOptions ho;
  ho.team = app_.team_of(s_.settings);
  ho.durable = app_.has_stores();
  for (SimAgentSpec& spec : specs)
    for (std::size_t r = 0; r < ho.team.robots.size(); ++r)
      if (spec.name.rfind(ho.team.robots[r] + "-", 0) == 0) spec.robot = static_cast<int>(r);
  ho.seed = seed_;
  ho.replicator = SimConfig::default_replicator();
  ho.locks.lease_ns = 1'000'000'000;
  ho.world_json = world;
  ho.log = log_;
  host_ = std::make_unique<AgentHost>(std::move(specs), ho);
  if (Status st = app_.start(*this); !st.ok()) {
    fail(st.error().to_string());
    return out;
  }
  if (Status st = host_->start(); !st.ok()) {
    fail(st.error().to_string());
    return out;
  }
  schedule_faults(*host_, s_.faults, log_, counts_);
  std::vector<std::unique_ptr<Workload>> workloads;
  for (auto it = s_.workloads.begin(); it != s_.workloads.end(); ++it) {
    auto w = (*app_.workload_factory(it.key()))(it.value(), "/workloads/" + it.key());
    if (w.ok() && *w) workloads.push_back(std::move(*w));
  }
  std::vector<std::unique_ptr<Check>> checks;
  for (auto it = s_.checks.begin(); it != s_.checks.end(); ++it) {
    auto c = (*app_.check_factory(it.key()))(it.value(), "/checks/" + it.key());
    if (c.ok() && *c) checks.push_back(std::move(*c));
  }
  for (auto& w : workloads) w->start(*this);
  for (auto& c : checks) c->start(*this);
  const auto limit = static_cast<std::int64_t>(s_.limit_s * 1e9);
  while (host_->now() < limit && !app_.done(*this)) host_->run_until(host_->now() + 100'000'000);
  app_.settle_run(*this);
  for (auto& c : checks) c->finish(*this, out.failures);
  if (out.failures.size() > 20) out.failures.resize(20);
  app_.add_report(*this, metrics_);
  out.metrics = metrics_;
  out.metrics["kills"] = counts_.kills;
  out.metrics["partitions"] = counts_.partitions;
  out.metrics["rejected"] = host_->rejected();
  out.metrics["seconds"] = static_cast<double>(host_->now()) / 1e9;
  out.passed = out.failures.empty();
  return out;
}

ScenarioOutcome run_scenario(const Scenario& s, const ScenarioApp& app, std::uint64_t seed,
                             std::function<void(std::int64_t, const std::string&)> log) {
  ScenarioRun run(s, app, seed, std::move(log));
  return run.run();
}

}  // namespace quiver::sim
