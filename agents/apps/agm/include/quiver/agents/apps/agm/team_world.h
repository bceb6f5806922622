#pragma once
/// @file
/// The team scenario (docs/teams.md): seed 001's clean-the-table world with several robots. Each
/// robot has its own body, gripper and plan node (RobotNames::of(tag)), starts in the kitchen,
/// and runs its own agents: navigation, rooms, grasping and a planner that plans for this robot
/// alone, without the other robots and what they carry. Its mission: nothing left on the table,
/// every object it sees in the kitchen, and its hand empty. Two robots both planning to fetch the
/// same mug first compete for it: the grasp holds a priority lock on the mug across robots, the
/// grammar refuses a grasp of a mug another robot carries, and the hand (Custody) closes on a mug
/// only one robot holds; the loser's planner then sees the mug gone and plans again.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "quiver/agents/apps/agm/agm_schema.h"
#include "quiver/agents/apps/agm/platform.h"
#include "quiver/base/result.h"
#include "quiver/graph/graph.h"

namespace quiver::agents::inline apps::agm {

struct TeamRobot {
  std::string tag;  ///< "A", "B", ...: the team file's name of the robot
  RobotNames names;
  std::string agm_id;  ///< its id in plans and missions
  Pose2 start;         ///< where it stands in the kitchen at the start
};

/// The most robots the team world holds.
inline constexpr int kMaxTeamRobots = 8;

/// Robots A, B, ... (2 to kMaxTeamRobots).
std::vector<TeamRobot> team_robots(int robots);

/// The clean-the-table world (clean-table.json) with `robots` robots instead of one.
/// @returns kInvalidArgument for a count outside 2..kMaxTeamRobots.
Result<std::string> team_world_json(int robots);

/// The mission of one robot's planner (.aggt text).
std::string team_mission(const TeamRobot& robot);

/// What one robot's planner does not see: the other robots (and their grippers) and the objects
/// they carry.
bool hidden_from(const TeamRobot& robot, const graph::Graph& g, graph::NodeId n);

}  // namespace quiver::agents::inline apps::agm
