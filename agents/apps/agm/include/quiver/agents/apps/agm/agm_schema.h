#pragma once
/// @file
/// The AGM scenario's world model (seed 001): names of its nodes, edges and attributes, the
/// embedded world and grammars, and the room geometry the agents share. Rooms carry their limits
/// as a polygon attribute (`limits`: double_vec x0, y0, x1, y1, ... in the world frame, metres);
/// `a -[transitable]-> b` says the robot can drive from room a to room b.
#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "quiver/graph/graph.h"
#include "quiver/base/result.h"

namespace quiver::agents::inline apps::agm {

namespace node {
inline constexpr const char* kWorld = "world";
inline constexpr const char* kRobot = "robot";
inline constexpr const char* kGripper = "gripper";
}  // namespace node

/// The nodes of one robot: its body, its gripper and the plan node its planner writes and its
/// agents follow. One robot: `robot`, `gripper`, `plan`; in a team (team_world.h) each robot's own,
/// `robotA`, `gripperA`, `planA` for robot A.
struct RobotNames {
  std::string robot = node::kRobot, gripper = node::kGripper, plan = "plan";
  /// The names of the team's robot called `tag` (empty: the single robot's).
  static RobotNames of(std::string_view tag);
};

namespace edge {
inline constexpr const char* kIn = "in";
inline constexpr const char* kTransitable = "transitable";
/// Unary predicate: the self-loop robot -> robot, present while the platform moved lately.
inline constexpr const char* kMoved = "movedInLastSeconds";
inline constexpr const char* kReach = "reach";
inline constexpr const char* kNoReach = "noReach";
/// Clean the table: the object stands on the table (o -[on]-> table).
inline constexpr const char* kOn = "on";
/// The robot's task: fetch this object (given by the world, or by a planner).
inline constexpr const char* kFetch = "fetch";
/// Intermediate state: the grasping agent IS EXECUTING a grasp of this object.
inline constexpr const char* kGrasping = "grasping";
inline constexpr const char* kCarrying = "carrying";
}  // namespace edge

namespace attr {
inline constexpr const char* kLimits = "limits";
/// On the robot: when the platform started its route, and when it was released from its wait
/// for the grasp (nanoseconds of the agents' clock): enough to replay the platform's motion.
inline constexpr const char* kRouteT0 = "route_t0_ns";
inline constexpr const char* kRouteRelease = "route_release_ns";
/// On rooms (clean the table): where the navigation agent drives to enter the room (double_vec
/// x, y); without it, the centre of the room's limits.
inline constexpr const char* kWaypoint = "waypoint";
}  // namespace attr

/// The clean-the-table mission (seed 001, section IV): its world (clean-table.json: two mugs on
/// the table, a plan node, AGM ids), the planner's domain (clean_table.aggl) and the mission
/// (clean-table.aggt). The mission's name for `--mission`.
inline constexpr const char* kCleanTable = "clean-table";

/// The contents of an embedded file ("agm.json", "navigation.aggl", ...), or "" if none.
std::string_view embedded_file(std::string_view name);
/// The scenario's world (JSON world file, format 1).
inline std::string_view world_json() { return embedded_file("agm.json"); }
/// The grammar of `role` (navigation, rooms, grasping, humans), or "".
std::string_view role_grammar(std::string_view role);

/// The visible node called `name`, or the null id.
graph::NodeId node_id(const graph::Graph& g, std::string_view name);

/// A simple polygon in the world's xy plane.
struct Polygon {
  std::vector<std::array<double, 2>> points;
  /// Even-odd rule; points on the boundary count on one side only, so two rooms sharing a wall
  /// never both contain a point of it.
  bool contains(double x, double y) const;
};

/// A room's `limits`. @returns kNotFound without the attribute, kInvalidArgument (naming the
/// room) for fewer than three points or an odd count.
Result<Polygon> room_limits(const graph::Graph& g, graph::NodeId room);
/// The room of `who`: the target of its `in` edge to a node of type room (the lowest id if a
/// merge left two), or nullopt.
std::optional<graph::NodeId> room_of(const graph::Graph& g, graph::NodeId who);
/// The room whose limits contain (x, y), or nullopt.
std::optional<graph::NodeId> room_at(const graph::Graph& g, double x, double y);
/// The shortest chain of rooms from `from` to `to` along transitable edges, both included
/// (just `from` when equal); empty when `to` cannot be reached.
std::vector<graph::NodeId> room_path(const graph::Graph& g, graph::NodeId from, graph::NodeId to);

/// The step a plan node asks for next (attributes `steps`, `next`, `status` of the planner agent,
/// agents/rules/planner): its rule and its binding, variables to the graph's nodes (a node named by its
/// `agm_id` or its name).
struct PlanStep {
  std::string rule;
  std::map<std::string, graph::NodeId> binding;
  std::int64_t version = 0, index = 0;
  graph::NodeId at(const std::string& var) const {
    auto it = binding.find(var);
    return it == binding.end() ? graph::NodeId{} : it->second;
  }
};
/// The next step of the plan node `plan_node`, or nullopt (no plan node, not executing, no step
/// left, or a step naming nodes the graph lacks).
std::optional<PlanStep> next_plan_step(const graph::Graph& g, std::string_view plan_node = "plan");

/// The position of `n` in the world frame, composing the RT edges up to the root, or nullopt
/// when `n` hangs from nothing.
std::optional<std::array<double, 3>> world_position(const graph::Graph& g, graph::NodeId n);

}  // namespace quiver::agents::inline apps::agm
