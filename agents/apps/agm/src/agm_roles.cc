// The AGM app's roles by name: which agent `quiver run ROLE` makes for navigation, rooms,
// grasping, humans and the planner, with the options they share.
#include "quiver/agents/apps/agm/agm_roles.h"

#include <nlohmann/json.hpp>

#include "quiver/agents/apps/agm/agm_schema.h"
#include "quiver/agents/apps/planning/planner_agent.h"

namespace quiver::agents::inline apps::agm {

const std::vector<std::string>& role_names() {
  static const std::vector<std::string> kRoles = {"navigation", "rooms", "grasping", "humans"};
  return kRoles;
}

bool is_role(std::string_view role) {
  for (const auto& r : role_names())
    if (r == role) return true;
  return false;
}

bool is_role_or_planner(std::string_view role) { return is_role(role) || role == kPlannerRole; }

namespace {

Result<std::unique_ptr<Agent>> make_agent(std::string_view role, const AgmRoleOptions& o) {
  auto name = [&](std::string_view fallback) {
    return o.name.empty() ? std::string(fallback) : o.name;
  };
  const bool clean_table = o.clean_table || o.team.has_value();
  const RobotNames names = o.team ? o.team->names : RobotNames{};
  if (role == "navigation") {
    auto platform = o.platform ? o.platform
                    : o.team   ? std::make_shared<Platform>(std::vector<Leg>{}, o.team->start)
                               : std::make_shared<Platform>(
                                   clean_table ? std::vector<Leg>{} : default_route(), default_start());
    NavigationOptions n = o.navigation;
    if (o.team) n.names = names;
    n.follow_plan = n.follow_plan || clean_table;
    n.measure_humans = n.measure_humans || o.measure_humans;
    return std::unique_ptr<Agent>(std::make_unique<Navigation>(platform, n, name(role)));
  }
  if (role == "rooms") {
    RoomsOptions r = o.rooms;
    if (o.team) r.names = names;
    r.measure_humans = r.measure_humans || o.measure_humans;
    return std::unique_ptr<Agent>(std::make_unique<Rooms>(r, name(role)));
  }
  if (role == "grasping") {
    GraspingOptions gr = o.grasping;
    gr.measure_humans = gr.measure_humans || o.measure_humans;
    gr.follow_plan = gr.follow_plan || clean_table;
    if (o.team) {
      gr.names = names;
      gr.lock_objects = true;
    }
    return std::unique_ptr<Agent>(std::make_unique<Grasping>(gr, name(role)));
  }
  if (role == "humans")
    return std::unique_ptr<Agent>(std::make_unique<Humans>(o.humans, name(role)));
  if (role == kPlannerRole) {
    planning::PlannerAgentOptions p;
    p.domain_text = std::string(embedded_file("clean_table.aggl"));
    p.domain_source = "clean_table.aggl";
    p.mission_text = std::string(embedded_file("clean-table.aggt"));
    p.mission_source = "clean-table.aggt";
    p.planner.max_expansions = o.planner_max_expansions;
    if (o.team) {
      p.plan_node = names.plan;
      p.mission_text = team_mission(*o.team);
      p.mission_source = "team mission of robot " + o.team->tag;
      p.hide = [robot = *o.team](const graph::Graph& g, graph::NodeId n) { return hidden_from(robot, g, n); };
    }
    if (o.measure_humans) {
      auto probe = std::make_shared<LatencyProbe>();
      p.on_setup = [probe](Agent& a, AgentContext& ctx) { probe->attach(a, ctx); };
      p.on_status = [probe](nlohmann::json& out) { probe->to_json(out["humans_latency"]); };
    }
    return std::unique_ptr<Agent>(std::make_unique<planning::PlannerAgent>(p, name(role)));
  }
  std::string known;
  for (const auto& r : role_names()) known += (known.empty() ? "" : ", ") + r;
  known += std::string(", ") + kPlannerRole;
  return make_error(ErrorCode::kInvalidArgument,
                    "unknown AGM role '" + std::string(role) + "' (roles: " + known + ")");
}

}  // namespace

Result<std::unique_ptr<Agent>> make_role(std::string_view role, const AgmRoleOptions& o) {
  auto a = make_agent(role, o);
  if (!a.ok()) return a;
  for (const auto& other : role_names()) {
    if (!o.team && other != role)
      (*a)->add_peer_grammar(other, std::string(role_grammar(other)), other + ".aggl");
    if (o.team)  // every robot's agents of each role, this one's included
      for (const TeamRobot& r : team_robots(o.team_size))
        if (r.tag + "-" + other != (*a)->name())
          (*a)->add_peer_grammar(r.tag + "-" + other, std::string(role_grammar(other)), other + ".aggl");
  }
  return a;
}

}  // namespace quiver::agents::inline apps::agm
