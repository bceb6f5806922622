// The rooms agent: commits changeRoom when the robot's pose crosses into another room.
#include "quiver/agents/apps/agm/rooms.h"

#include <nlohmann/json.hpp>

#include "quiver/agents/apps/agm/agm_schema.h"

namespace quiver::agents::inline apps::agm {

using graph::NodeId;
using graph::Symbol;
using graph::Value;

Rooms::Rooms(RoomsOptions o, std::string name) : Agent(std::move(name)), opt_(std::move(o)) {
  set_grammar_text(std::string(role_grammar("rooms")), "rooms.aggl");
}

void Rooms::setup(AgentContext& ctx) {
  ChangeFilter poses;
  poses.edge_types = {"RT"};
  subscribe(poses, [this](AgentContext& c, const graph::ChangeBatch& b) {
    const NodeId robot = node_id(c.graph(), opt_.names.robot);
    for (const graph::EdgeChange& e : b.edges)
      if (e.key.to == robot && e.kind != graph::ChangeKind::kDeleted) {
        check(c);
        return;
      }
  });
  if (opt_.measure_humans) probe_.attach(*this, ctx);
  check(ctx);  // the pose may have moved while this agent was away
}

void Rooms::check(AgentContext& ctx) {
  graph::Graph& g = ctx.graph();
  const NodeId robot = node_id(g, opt_.names.robot);
  if (robot.is_null()) return;
  auto X_WR = g.rt_edge(robot);
  auto here = room_of(g, robot);
  if (!X_WR || !here) return;
  const double x = X_WR->pose.translation[0], y = X_WR->pose.translation[1];
  if (auto limits = room_limits(g, *here); limits.ok() && limits->contains(x, y)) return;
  auto there = room_at(g, x, y);
  if (!there) {
    ++outside_;  // between rooms' limits (a doorway not drawn): wait for a pose inside one
    return;
  }
  const std::vector<NodeId> path = room_path(g, *here, *there);
  if (path.size() < 2) {
    ctx.log("no transitable path from " + g.name_of(*here) + " to " + g.name_of(*there));
    ++refused_;
    return;
  }
  for (std::size_t i = 0; i + 1 < path.size(); ++i) {
    const NodeId a = path[i], b = path[i + 1];
    const std::int64_t now = ctx.now();
    graph::Transaction tx = g.begin();
    Status s = tx.delete_edge(robot, a, Symbol(edge::kIn));
    if (s.ok())
      s = tx.insert_edge(robot, b, Symbol(edge::kIn),
                         {{Symbol("x"), Value(x)},
                          {Symbol("y"), Value(y)},
                          {Symbol("stamp_ns"), Value(X_WR->stamp)},
                          {Symbol("committed_ns"), Value(now)}});
    // What the robot carries changes room with it (the rule's forall).
    for (const graph::EdgeKey& c : g.edges_from(robot, edge::kCarrying))
      if (s.ok() && g.has_edge(c.to, a, edge::kIn)) {
        s = tx.delete_edge(c.to, a, Symbol(edge::kIn));
        if (s.ok()) s = tx.insert_edge(c.to, b, Symbol(edge::kIn));
      }
    if (s.ok()) {
      if (auto c = tx.commit(); !c.ok()) s = c.error();
    }
    if (!s.ok()) {
      ++refused_;
      ctx.log("changeRoom " + g.name_of(a) + " -> " + g.name_of(b) +
              " refused: " + s.error().to_string());
      return;
    }
    RoomChange rc{g.name_of(a), g.name_of(b), x, y, X_WR->stamp, now};
    ctx.log("changeRoom " + rc.from + " -> " + rc.to);
    changes_.push_back(rc);
    if (opt_.on_change) opt_.on_change(rc);
  }
}

void Rooms::status(nlohmann::json& out) const {
  out["room_changes"] = changes_.size();
  out["refused"] = refused_;
  if (opt_.measure_humans) probe_.to_json(out["humans_latency"]);
}

}  // namespace quiver::agents::inline apps::agm
