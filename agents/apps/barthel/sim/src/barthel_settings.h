#pragma once
// Private: the Barthel keys of a scenario file ("patient", "timing"), read into typed values.

#include <nlohmann/json.hpp>
#include <string>

#include "quiver/agents/apps/barthel/sim/barthel_scenario.h"

namespace quiver::agents::inline apps::barthel::internal {

/// Reads the app's keys of a scenario (every key the simulator does not know): an unknown key, or
/// a bad value, is kInvalidArgument naming `source` and the JSON pointer. Fills what the keys set.
Status read_settings(const nlohmann::json& keys, const std::string& source, PatientScript& script,
                     ScenarioTiming& timing);
/// The keys of `script` and `timing`, as read_settings() reads them.
nlohmann::json write_settings(const PatientScript& script, const ScenarioTiming& timing);

}  // namespace quiver::agents::inline apps::barthel::internal
