#pragma once
/// @file
/// The AGM scenario's agents by role name: `quiver run ROLE`, `quiver scenario agm`,
/// `quiver bench humans` and the simulator create them here. Each agent verifies the others'
/// changes against their own grammars.
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "quiver/agents/apps/agm/grasping.h"
#include "quiver/agents/apps/agm/humans.h"
#include "quiver/agents/apps/agm/navigation.h"
#include "quiver/agents/apps/agm/rooms.h"
#include "quiver/agents/apps/agm/team_world.h"
#include "quiver/base/result.h"

namespace quiver::agents::inline apps::agm {

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
  /// Clean the table (schema.h, kCleanTable): navigation and grasping follow the plan node's next
  /// step (navigation with no fixed route: a Platform with no legs, from default_start()).
  bool clean_table = false;
  /// agm-planner: the planner agent's search bound (expansions).
  std::int64_t planner_max_expansions = 200'000;
  /// A team (team_world.h): the robot the agent works for. Navigation, rooms and grasping use its
  /// nodes; grasping locks the object it grasps; the planner writes the robot's plan node, plans
  /// the robot's own mission and does not see the other robots. Implies clean_table.
  std::optional<TeamRobot> team;
  /// A team: how many robots it has (their agents, `A-navigation`, ..., are the peers whose
  /// changes each agent verifies with their grammars).
  int team_size = 2;
};

/// The planner agent of the clean-the-table mission (agents/apps/planning's PlannerAgent with the
/// embedded domain clean_table.aggl and mission clean-table.aggt): a role of its own, outside
/// role_names() (the fixed-route scenario has no planner).
inline constexpr const char* kPlannerRole = "agm-planner";

/// navigation, rooms, grasping, humans.
const std::vector<std::string>& role_names();
bool is_role(std::string_view role);

/// role_names() and kPlannerRole.
bool is_role_or_planner(std::string_view role);

/// @returns the agent, or kInvalidArgument naming an unknown role (and listing the known ones).
Result<std::unique_ptr<Agent>> make_role(std::string_view role, const AgmRoleOptions& o);

}  // namespace quiver::agents::inline apps::agm
