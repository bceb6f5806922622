#pragma once
/// @file
/// The Barthel agents by role name, with their devices: `quiver run ROLE`, the scenario runner and
/// the simulator create them here. Real devices (espeak-ng audio, OpenCV screen images, a JSON
/// result file, a pager file) write into `out_dir`; without one, devices are simulated.
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "quiver/agents/apps/barthel/inputs.h"
#include "quiver/agents/apps/barthel/panel.h"
#include "quiver/agents/apps/barthel/patient_script.h"
#include "quiver/agents/apps/barthel/person.h"
#include "quiver/agents/apps/barthel/test_planner.h"
#include "quiver/agents/apps/barthel/speech.h"
#include "quiver/base/result.h"

namespace quiver::agents::inline apps::barthel {

struct RoleOptions {
  std::string out_dir;  ///< real devices write here; empty: simulated devices
  bool simulated_speech = false;  ///< simulated speech even with out_dir (quick tests)
  std::string name;     ///< the agent's name; empty: the role's own (a second planner needs another)
  TruthSource truth;    ///< the simulated patient's truth; empty: the agent's own replica
  PatientScript script = PatientScript::random(1);
  PlannerOptions planner;
  SpeechOptions speech;
  PanelOptions panel;
  PersonOptions person;
  /// The Planner's result store and pager when they must outlive it (the simulator); else the
  /// Planner owns a JSON file store and a pager file in out_dir (memory ones without).
  devices::ResultStore* store = nullptr;
  devices::Pager* pager = nullptr;
  /// Simulated speech: an utterance lasts base + words * per_word.
  std::int64_t sim_ns_per_word = 250'000'000;
  std::int64_t sim_base_ns = 300'000'000;
};

/// planner, speech, panel, person, patient.
const std::vector<std::string>& role_names();

/// @returns the agent, or kInvalidArgument naming an unknown role (and listing the known ones).
Result<std::unique_ptr<Agent>> make_role(std::string_view role, const RoleOptions& o);

}  // namespace quiver::agents::inline apps::barthel
