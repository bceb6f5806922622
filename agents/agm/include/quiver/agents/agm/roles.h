#pragma once
/// @file
/// The AGM scenario's agents by role name: `quiver run ROLE`, `quiver scenario agm`,
/// `quiver bench humans` and the simulator create them here. Each agent verifies the others'
/// changes against their own grammars.
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "quiver/agents/agm/grasping.h"
#include "quiver/agents/agm/humans.h"
#include "quiver/agents/agm/navigation.h"
#include "quiver/agents/agm/rooms.h"
#include "quiver/result.h"

namespace quiver::agents::agm {

struct AgmRoleOptions {
  std::string name;  ///< the agent's name; empty: the role's
  /// navigation: the platform it drives; null: its own, on default_route() from default_start().
  std::shared_ptr<Platform> platform;
  NavigationOptions navigation;
  RoomsOptions rooms;
  GraspingOptions grasping;
  HumansOptions humans;
  /// navigation, rooms, grasping: measure how fresh the human joints are when they arrive.
  bool measure_humans = false;
};

/// navigation, rooms, grasping, humans.
const std::vector<std::string>& role_names();
bool is_role(std::string_view role);

/// @returns the agent, or kInvalidArgument naming an unknown role (and listing the known ones).
Result<std::unique_ptr<Agent>> make_role(std::string_view role, const AgmRoleOptions& o);

}  // namespace quiver::agents::agm
