// The team scenario's world, missions and planner views (team_world.h).
#include "quiver/agents/apps/agm/team_world.h"

#include <nlohmann/json.hpp>

namespace quiver::agents::inline apps::agm {

using nlohmann::json;

std::vector<TeamRobot> team_robots(int robots) {
  std::vector<TeamRobot> out;
  for (int r = 0; r < robots && r < kMaxTeamRobots; ++r) {
    TeamRobot t;
    t.tag = std::string(1, static_cast<char>('A' + r));
    t.names = RobotNames::of(t.tag);
    // Robot A keeps the single robot's id; the others get ids no node of the world uses.
    t.agm_id = r == 0 ? "1" : std::to_string(100 + r);
    // In a column along the kitchen's west wall, facing east.
    t.start = {1.0, 0.6 + 0.9 * (r % 4), 0.0};
    if (r >= 4) t.start.x = 2.0;
    out.push_back(std::move(t));
  }
  return out;
}

Result<std::string> team_world_json(int robots) {
  if (robots < 2 || robots > kMaxTeamRobots)
    return make_error(ErrorCode::kInvalidArgument, "a team has 2 to " + std::to_string(kMaxTeamRobots) +
                                                       " robots, not " + std::to_string(robots));
  json w = json::parse(embedded_file("clean-table.json"));
  const RobotNames one;
  auto is_robots = [&](const std::string& n) { return n == one.robot || n == one.gripper || n == one.plan; };
  json robot_node, gripper_node, gripper_rt;
  json nodes = json::array(), edges = json::array(), rt = json::array();
  for (const json& n : w["nodes"]) {
    const std::string name = n["name"];
    if (name == one.robot) robot_node = n;
    if (name == one.gripper) gripper_node = n;
    if (!is_robots(name)) nodes.push_back(n);
  }
  std::vector<json> robot_edges;
  for (const json& e : w["edges"]) {
    if (e["from"] == one.robot) robot_edges.push_back(e);
    else if (!is_robots(e["from"]) && !is_robots(e["to"])) edges.push_back(e);
  }
  for (const json& r : w["rt"]) {
    if (r["parent"] == one.robot && r["child"] == one.gripper) gripper_rt = r;
    if (!is_robots(r["parent"]) && !is_robots(r["child"])) rt.push_back(r);
  }
  for (const TeamRobot& t : team_robots(robots)) {
    json body = robot_node;
    body["name"] = t.names.robot;
    body["attrs"]["agm_id"] = t.agm_id;
    body["attrs"]["label"] = "shelly-" + t.tag;
    nodes.push_back(body);
    json hand = gripper_node;
    hand["name"] = t.names.gripper;
    nodes.push_back(hand);
    nodes.push_back({{"name", t.names.plan}, {"type", "plan"}});
    for (json e : robot_edges) {
      e["from"] = t.names.robot;
      edges.push_back(e);
    }
    rt.push_back({{"parent", "world"}, {"child", t.names.robot}, {"translation", {t.start.x, t.start.y, 0}}});
    json g = gripper_rt;
    g["parent"] = t.names.robot;
    g["child"] = t.names.gripper;
    rt.push_back(g);
  }
  w["nodes"] = nodes;
  w["edges"] = edges;
  w["rt"] = rt;
  return w.dump(1);
}

std::string team_mission(const TeamRobot& robot) {
  const std::string& k = robot.agm_id;
  return "{\n\t" + k + ":robot\n\t2:room\n\t5:table\n}\nprecondition\n{\n"
         "\t(and (not (exists o:object (on o 5)))\n"
         "\t     (forall o:object (in o 2))\n"
         "\t     (not (exists o:object (carrying " + k + " o))))\n}\n";
}

bool hidden_from(const TeamRobot& robot, const graph::Graph& g, graph::NodeId n) {
  const std::string_view type = g.type_of(n).str();
  if (type == "robot" || type == "gripper") return g.name_of(n) != robot.names.robot && g.name_of(n) != robot.names.gripper;
  for (const graph::EdgeKey& e : g.edges_to(n, edge::kCarrying))
    if (g.name_of(e.from) != robot.names.robot) return true;
  return false;
}

}  // namespace quiver::agents::inline apps::agm
