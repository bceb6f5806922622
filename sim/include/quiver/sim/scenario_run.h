#pragma once
/// @file
/// Running a scenario (scenario.h) in the simulator: its agents on an AgentHost (each on the agent
/// engine, virtual time, the virtual network carrying the samples DDS would), its fault schedule,
/// workloads and checks, until the app says it is done or the time limit passes; then the app
/// settles the run (ScenarioApp::settle()) and the checks finish. One seed replays a run exactly.
///
/// Threading: the simulator's one thread.

#include <any>
#include <cstdint>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "quiver/sim/agent_host.h"
#include "quiver/sim/fault_model.h"
#include "quiver/sim/scenario.h"
#include "quiver/sim/scenario_app.h"

namespace quiver::sim {

/// What a run ends with: whether every check held, what failed, and its figures (the app's and
/// the run's: "kills", "partitions", "rejected", "seconds").
struct ScenarioOutcome {
  std::string name;
  std::uint64_t seed = 0;
  bool passed = false;
  std::vector<std::string> failures;
  nlohmann::json metrics = nlohmann::json::object();
  nlohmann::json to_json() const;
};

/// One run, as the app's roles, checks and workloads see it.
class ScenarioRun {
 public:
  ScenarioRun(const Scenario& s, const ScenarioApp& app, std::uint64_t seed,
              std::function<void(std::int64_t, const std::string&)> log);
  const Scenario& scenario() const { return s_; }
  const ScenarioApp& app() const { return app_; }
  std::uint64_t seed() const { return seed_; }
  AgentHost& host() { return *host_; }
  /// The state the app's agents share over the run (set in ScenarioApp::on_start()).
  std::any& state() { return state_; }
  template <class T>
  T& state_as() {
    return std::any_cast<T&>(state_);
  }
  /// While a role factory runs: the name of the agent it makes (a role may run under several
  /// names, e.g. {"role": "ponger", "name": "backup"}).
  const std::string& agent_name() const { return making_; }
  /// A line for the run's log, at the current virtual time.
  void note(const std::string& line);
  const FaultCounts& faults() const { return counts_; }
  /// The app's run-level figures (its report adds to them).
  nlohmann::json& metrics() { return metrics_; }

  /// Runs it: @returns the outcome.
  ScenarioOutcome run();

 private:
  const Scenario& s_;
  const ScenarioApp& app_;
  std::uint64_t seed_;
  std::function<void(std::int64_t, const std::string&)> log_;
  std::any state_;  ///< outlives the host: the agents may hold pointers into it
  std::unique_ptr<AgentHost> host_;
  std::string making_;
  FaultCounts counts_;
  nlohmann::json metrics_ = nlohmann::json::object();
};

/// Runs `s` with `app`'s roles, checks and workloads, from `seed`. `log` gets every line (the
/// agents' and the host's) with its virtual time.
ScenarioOutcome run_scenario(const Scenario& s, const ScenarioApp& app, std::uint64_t seed,
                             std::function<void(std::int64_t t_ns, const std::string&)> log = {});

}  // namespace quiver::sim
