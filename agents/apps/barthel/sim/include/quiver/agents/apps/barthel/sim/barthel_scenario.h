#pragma once
/// @file
/// The Barthel test in the simulator: the app's registration with it (barthel_app(): its roles,
/// its settings "patient" and "timing", its checks, its shared devices and when a run is done),
/// and the typed scenario that tests and `quiver sim --scenario` use. A scenario file is the
/// simulator's (sim/scenario.h) with the Barthel keys:
///
/// ```json
/// {"name": "person-lost", "patient": {"script": {...}} | {"seed": 7, "varied": true},
///  "faults": [{"at_s": 20, "partition": [["planner"], ["speech", "panel"]]}, {"at_s": 22, "heal": true},
///             {"at_s": 30, "kill": "planner"}, {"at_s": 31, "restart": "planner"}, {"at_s": 5, "loss": 0.2}],
///  "checks": {"never_speaking_absent_ms": 300, "no_item_asked_twice": true,
///             "result_matches_script": true, "status": "completed", "total": 85},
///  "timing": {"words_ms": 250, "think_ms": [300, 1500], "answer_timeout_s": 8, "person_hz": 30, "joints": true},
///  "limit_s": 900}
/// ```
#include <cstdint>
#include <functional>
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string>
#include <vector>

#include "quiver/agents/apps/barthel/patient_script.h"
#include "quiver/base/result.h"
#include "quiver/sim/fault_model.h"
#include "quiver/sim/scenario_app.h"

namespace quiver::agents::inline apps::barthel {

/// The Barthel app as the simulator runs it (built once).
const sim::ScenarioApp& barthel_app();

struct ScenarioChecks {
  std::int64_t never_speaking_absent_ms = 300;  ///< <= 0: off
  bool no_item_asked_twice = true;
  bool result_matches_script = true;
  std::optional<std::string> status;  ///< the stored result's status must be this
  std::optional<int> total;           ///< and its total this
};

struct ScenarioTiming {
  double words_ms = 250, base_ms = 300;  ///< simulated speech
  double answer_timeout_s = 8;
  double person_hz = 30;
  bool joints = true;
};

struct BarthelScenario {
  std::string name = "barthel";
  std::vector<std::string> agents = {"planner", "speech", "panel", "person", "patient"};
  std::string world_file;  ///< empty: the embedded Barthel world
  PatientScript script;
  std::vector<sim::FaultEvent> faults;
  ScenarioChecks checks;
  ScenarioTiming timing;
  double limit_s = 900;

  /// @returns kInvalidArgument naming `source` and the JSON pointer of a bad value.
  static Result<BarthelScenario> parse(const nlohmann::json& j, const std::string& source);
  static Result<BarthelScenario> load(const std::string& path);
  nlohmann::json to_json() const;
  /// A varied patient and random faults (loss up to 30%, partitions, kill -9 and restart of any
  /// robot agent, the Planner included), all drawn from `seed`; fast speech and no joints.
  static BarthelScenario random_faults(std::uint64_t seed);
};

struct BarthelResult {
  std::string name;
  std::uint64_t seed = 0;
  bool passed = false;
  std::vector<std::string> failures;
  std::string status;           ///< the stored result's ("" if none)
  int total = -1;
  std::string expected_status;
  int expected_total = -1;
  double finished_s = -1;       ///< virtual time the result was stored
  double max_speaking_absent_ms = 0;
  int interruptions = 0;        ///< utterances stopped mid-sentence
  int kills = 0, partitions = 0;
  std::uint64_t rejected = 0;
  nlohmann::json to_json() const;
};

/// Runs `s` in the simulator with `seed` (network and agents' randomness). `log` gets every line
/// (agents' and the host's) with its virtual time.
BarthelResult run_scenario(const BarthelScenario& s, std::uint64_t seed,
                           std::function<void(std::int64_t t_ns, const std::string&)> log = {});

}  // namespace quiver::agents::inline apps::barthel
