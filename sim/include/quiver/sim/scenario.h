#pragma once
/// @file
/// Scenarios as data (docs/simulation.md): which agents run (by the roles an app registered), on
/// which world, under which faults (the one fault model: fault_model.h), what workloads drive
/// them and what must hold (checks by registered name), for how long. The simulator knows no app:
/// the keys it does not know belong to the app (ScenarioApp::settings()).
///
/// ```json
/// {"name": "person-lost", "app": "barthel",
///  "agents": ["planner", "speech", {"role": "person", "name": "camera"}],
///  "world": "examples/worlds/kitchen.json",
///  "faults": [{"at_s": 20, "partition": [["planner"], ["speech"]]}, {"at_s": 22, "heal": true},
///             {"at_s": 30, "kill": "planner"}, {"at_s": 31, "restart": "planner"}, {"at_s": 5, "loss": 0.2}],
///  "workloads": {"churn": {"steps": 200}},
///  "checks": {"never_speaking_absent_ms": 300, "status": "completed"},
///  "limit_s": 900,
///  "patient": {...}}
/// ```

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "quiver/base/result.h"
#include "quiver/sim/fault_model.h"
#include "quiver/sim/scenario_app.h"

namespace quiver::sim {

struct ScenarioAgent {
  std::string role;
  std::string name;  ///< unique in the scenario (the role's name unless the file gives one)
};

struct Scenario {
  std::string name = "scenario";
  std::string app;                       ///< the app whose roles it runs (informative; the caller picks the app)
  std::vector<ScenarioAgent> agents;     ///< empty: the app's default agents
  std::string world_file;                ///< empty: the app's default world
  std::vector<FaultEvent> faults;
  nlohmann::json workloads = nlohmann::json::object();  ///< name -> parameters
  nlohmann::json checks = nlohmann::json::object();     ///< name -> parameters
  nlohmann::json settings = nlohmann::json::object();   ///< the app's own keys
  double limit_s = 900;

  /// Reads a scenario for `app`: generic keys here, the app's through ScenarioApp::settings();
  /// every agent names one of its roles, every check and workload one it registered (and its
  /// parameters are checked by making it once). @returns kInvalidArgument naming `source` and the
  /// JSON pointer of the bad value.
  static Result<Scenario> parse(const nlohmann::json& j, const std::string& source, const ScenarioApp& app);
  /// parse() of a file; kIo when it cannot be read.
  static Result<Scenario> load(const std::string& path, const ScenarioApp& app);
  /// The JSON of a scenario file (for an app's typed scenario that reads its keys too): kIo when
  /// it cannot be read, kInvalidArgument naming `path` when it is not JSON.
  static Result<nlohmann::json> read(const std::string& path);
  nlohmann::json to_json() const;
  /// The agents it runs: its own, or the app's default roles.
  std::vector<ScenarioAgent> agents_of(const ScenarioApp& app) const;
};

}  // namespace quiver::sim
