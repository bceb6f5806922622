#pragma once
/// @file
/// What a scenario runs: an app's roles (agent classes by name), its own settings in a scenario
/// file, the state its agents share over one run (devices that outlive an agent's incarnation, a
/// ground truth), when a run is done, and its checks and workloads by name. The simulator knows
/// no app: each app registers itself by building a ScenarioApp (Barthel:
/// agents/apps/barthel/sim, AGM: agents/apps/agm/sim), and so does any project that embeds
/// Quiver (examples/sim_scenario).
///
/// Threading: the simulator's one thread.

#include <any>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "quiver/agents/runtime/api/agent.h"
#include "quiver/base/result.h"
#include "quiver/sim/agent_host.h"

namespace quiver::sim {

class ScenarioRun;

/// A check: watches a run (start() may sample it over time through ScenarioRun::host().every())
/// and says at its end what went wrong.
class Check {
 public:
  virtual ~Check() = default;
  virtual void start(ScenarioRun& run) {}
  /// Adds what failed to `failures` (empty: the check holds).
  virtual void finish(ScenarioRun& run, std::vector<std::string>& failures) = 0;
};

/// A workload: what the scenario does to its agents' world while it runs (e.g. a churn of writes).
class Workload {
 public:
  virtual ~Workload() = default;
  virtual void start(ScenarioRun& run) = 0;
};

class ScenarioApp {
 public:
  /// Makes the agent of a role for a run (again after every restart). Null: the role could not
  /// be made (the run reports it).
  using RoleFactory = std::function<std::unique_ptr<agents::Agent>(ScenarioRun& run)>;
  /// Makes a check from its parameters in a scenario file (`where`: their JSON pointer, for
  /// errors). @returns kInvalidArgument naming `where` for bad parameters.
  using CheckFactory =
      std::function<Result<std::unique_ptr<Check>>(const nlohmann::json& params, const std::string& where)>;
  using WorkloadFactory =
      std::function<Result<std::unique_ptr<Workload>>(const nlohmann::json& params, const std::string& where)>;

  explicit ScenarioApp(std::string name) : name_(std::move(name)) {}
  const std::string& name() const { return name_; }

  /// A role: scenario files name agents by role.
  ScenarioApp& role(std::string name, RoleFactory make);
  /// A check, by the name scenario files use under "checks".
  ScenarioApp& check(std::string name, CheckFactory make);
  /// A workload, by the name scenario files use under "workloads".
  ScenarioApp& workload(std::string name, WorkloadFactory make);
  /// The agents a scenario runs when its file names none, in order.
  ScenarioApp& default_agents(std::vector<std::string> roles);
  /// The same, chosen from the app's settings in the scenario (an app whose settings add or drop
  /// an agent). Fault events may name only the agents a scenario runs.
  ScenarioApp& default_agents(std::function<std::vector<std::string>(const nlohmann::json& settings)> roles);
  /// The world every replica is seeded with when the file names none (JSON world text).
  ScenarioApp& default_world(std::string world_json);
  /// The same, chosen from the app's settings in the scenario.
  ScenarioApp& default_world(std::function<std::string(const nlohmann::json& settings)> world_json);
  /// Checks the app's own top-level keys of a scenario file (all keys the simulator does not
  /// know); an unknown one is an error. `source` names the file. Without it, every key unknown to
  /// the simulator is refused.
  ScenarioApp& settings(std::function<Status(const nlohmann::json& app_keys, const std::string& source)> check);
  /// Called once the host is made, before it boots the agents (their roles are made later, on
  /// their first setup) and before faults and checks start: the app sets up the state its roles
  /// share (ScenarioRun::state()).
  ScenarioApp& on_start(std::function<Status(ScenarioRun&)> fn);
  /// Ends a run before its time limit (checked every 100 ms of virtual time).
  ScenarioApp& done_when(std::function<bool(ScenarioRun&)> fn);
  /// Called once a run is done (or its time is up), before the checks finish: the app brings the
  /// run to the state its final checks read, e.g. heals every fault, restarts every agent, quiets
  /// them and lets the replicas settle (ScenarioRun::host(): virtual time may advance; the checks
  /// that sample over time go on sampling). What it measures on the way goes in the run's state.
  ScenarioApp& settle(std::function<void(ScenarioRun&)> fn);
  /// Adds the app's figures to a run's outcome when it ends.
  ScenarioApp& report(std::function<void(ScenarioRun&, nlohmann::json& metrics)> fn);
  /// A robot team (AgentHostOptions::team, docs/teams.md): the robots and the team network's
  /// links, from the run's settings. Each agent runs on the robot whose name, with a dash, begins
  /// its own (`A-navigation` on robot A).
  ScenarioApp& team(std::function<AgentHostOptions::Team(const nlohmann::json& settings)> fn);
  /// The agents keep stores (AgentHostOptions::durable): a restart loads what the replica had.
  ScenarioApp& stores(bool on) {
    stores_ = on;
    return *this;
  }
  bool has_stores() const { return stores_; }

  // ---- for the runner ----
  bool has_role(const std::string& r) const { return roles_.count(r) > 0; }
  std::vector<std::string> roles() const;
  const RoleFactory& role_factory(const std::string& r) const { return roles_.at(r); }
  const CheckFactory* check_factory(const std::string& c) const;
  const WorkloadFactory* workload_factory(const std::string& w) const;
  std::vector<std::string> check_names() const;
  std::vector<std::string> default_agents(const nlohmann::json& settings) const;
  std::string default_world(const nlohmann::json& settings) const;
  Status check_settings(const nlohmann::json& app_keys, const std::string& source) const;
  Status start(ScenarioRun& run) const { return on_start_ ? on_start_(run) : Status{}; }
  bool done(ScenarioRun& run) const { return done_when_ && done_when_(run); }
  void settle_run(ScenarioRun& run) const {
    if (settle_) settle_(run);
  }
  void add_report(ScenarioRun& run, nlohmann::json& metrics) const {
    if (report_) report_(run, metrics);
  }
  AgentHostOptions::Team team_of(const nlohmann::json& settings) const { return team_ ? team_(settings) : AgentHostOptions::Team{}; }

 private:
  std::string name_;
  std::map<std::string, RoleFactory> roles_;
  std::map<std::string, CheckFactory> checks_;
  std::map<std::string, WorkloadFactory> workloads_;
  std::function<std::vector<std::string>(const nlohmann::json&)> default_agents_;
  std::function<std::string(const nlohmann::json&)> default_world_;
  std::function<Status(const nlohmann::json&, const std::string&)> settings_;
  std::function<Status(ScenarioRun&)> on_start_;
  std::function<bool(ScenarioRun&)> done_when_;
  std::function<void(ScenarioRun&)> settle_;
  std::function<void(ScenarioRun&, nlohmann::json&)> report_;
  std::function<AgentHostOptions::Team(const nlohmann::json&)> team_;
  bool stores_ = false;
};

/// A check that is on or off in a scenario file ("name": true; false makes none): `finish` adds
/// at the run's end what failed. Anything but true or false is refused, naming where it is.
ScenarioApp::CheckFactory switch_check(std::function<void(ScenarioRun&, std::vector<std::string>& failures)> finish);

}  // namespace quiver::sim
