// The navigation agent: drives the platform along its route or the plan and publishes its pose.
#include "quiver/agents/apps/agm/navigation.h"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "quiver/agents/apps/agm/agm_schema.h"

namespace quiver::agents::inline apps::agm {

using graph::NodeId;
using graph::Symbol;
using graph::Value;

Navigation::Navigation(std::shared_ptr<Platform> platform, NavigationOptions o, std::string name)
    : Agent(std::move(name)), platform_(std::move(platform)), opt_(o) {
  set_grammar_text(std::string(role_grammar("navigation")), "navigation.aggl");
}

void Navigation::setup(AgentContext& ctx) {
  // The route starts once: a restarted agent finds the start in the graph (the platform device
  // itself may have outlived the agent, as in the simulator).
  graph::Graph& g = ctx.graph();
  const NodeId robot = node_id(g, opt_.names.robot);
  if (!platform_->started() && opt_.resume_from_graph && !robot.is_null())
    if (auto X_WR = g.rt_edge(robot)) {
      const auto& q = X_WR->pose.rotation;  // w, x, y, z: a yaw about z
      platform_->relocate({X_WR->pose.translation[0], X_WR->pose.translation[1],
                           2 * std::atan2(q[3], q[0])});
    }
  if (!platform_->started()) {
    const Value* t0 = robot.is_null() ? nullptr : g.attr(robot, attr::kRouteT0);
    platform_->start(t0 && t0->get_if<std::int64_t>() ? *t0->get_if<std::int64_t>() : ctx.now());
    // ... and whether its wait for the grasp had already been released.
    const Value* rel = robot.is_null() ? nullptr : g.attr(robot, attr::kRouteRelease);
    if (rel && rel->get_if<std::int64_t>()) (void)platform_->release(*rel->get_if<std::int64_t>());
  }
  if (opt_.measure_humans) probe_.attach(*this, ctx);
  ctx.every(static_cast<std::int64_t>(1e9 / opt_.rate_hz), [this, &ctx] { frame(ctx); });
}

void Navigation::frame(AgentContext& ctx) {
  graph::Graph& g = ctx.graph();
  const NodeId robot = node_id(g, opt_.names.robot), world = node_id(g, node::kWorld);
  if (robot.is_null() || world.is_null()) return;
  const std::int64_t now = ctx.now();
  const bool moved = platform_->moved_between(now - opt_.moved_window_ns, now);
  const bool flagged = g.has_edge(robot, robot, edge::kMoved);
  if (opt_.follow_plan && platform_->finished(now)) steer(g, now);
  bool done = platform_->finished(now);
  if (opt_.follow_plan) {
    const NodeId plan = node_id(g, opt_.names.plan);
    const Value* st = plan.is_null() ? nullptr : g.attr(plan, "status");
    done = done && st && st->get_if<std::string>() && *st->get_if<std::string>() == "achieved";
  }
  if (opt_.quiet_when_done && done && !moved && !flagged) return;

  graph::Transaction tx = g.begin();
  Status s;
  if (!g.attr(robot, attr::kRouteT0)) s = tx.set(robot, attr::kRouteT0, Value(platform_->t0()));
  // The grasp is done: the platform may go on (the robot carries something it was to fetch).
  if (s.ok() && platform_->waiting(now) && !g.edges_from(robot, edge::kCarrying).empty() &&
      platform_->release(now))
    s = tx.set(robot, attr::kRouteRelease, Value(now));
  const Pose2 p = platform_->pose(now);
  graph::Pose X_WR;
  Rng& rng = ctx.rng();
  auto noise = [&] { return opt_.jitter_m * (2 * rng.uniform() - 1); };
  X_WR.translation = {p.x + noise(), p.y + noise(), 0.0};
  X_WR.rotation = {std::cos(p.yaw / 2), 0.0, 0.0, std::sin(p.yaw / 2)};
  if (s.ok()) s = tx.set_rt(world, robot, X_WR, now);
  // One rule at most per transaction: the predicate follows the odometry.
  if (s.ok() && moved && !flagged)
    s = tx.insert_edge(robot, robot, Symbol(edge::kMoved), {{Symbol("since_ns"), Value(now)}});
  if (s.ok() && !moved && flagged) s = tx.delete_edge(robot, robot, Symbol(edge::kMoved));
  if (!s.ok() || !tx.commit().ok()) {
    ++refused_;
    return;
  }
  ++frames_;
  if (moved && !flagged) ++moved_set_;
  if (!moved && flagged) ++moved_cleared_;
}

void Navigation::steer(const graph::Graph& g, std::int64_t now) {
  auto step = next_plan_step(g, opt_.names.plan);
  if (!step) return;
  double x = 0, y = 0, speed = opt_.speed;
  if (step->rule == "changeRoom") {
    const NodeId b = step->at("b");
    if (b.is_null()) return;
    const Value* w = g.attr(b, attr::kWaypoint);
    const auto* xy = w ? w->get_if<graph::DoubleVec>() : nullptr;
    if (xy && xy->size() == 2) {
      x = (*xy)[0];
      y = (*xy)[1];
    } else {
      auto limits = room_limits(g, b);
      if (!limits.ok()) return;
      double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
      for (auto [px, py] : limits->points) {
        x0 = std::min(x0, px);
        y0 = std::min(y0, py);
        x1 = std::max(x1, px);
        y1 = std::max(y1, py);
      }
      x = (x0 + x1) / 2;
      y = (y0 + y1) / 2;
    }
  } else if (step->rule == "approach") {
    auto p = world_position(g, step->at("o"));
    if (!p) return;
    x = (*p)[0] - opt_.approach_offset_m;
    y = (*p)[1];
    speed = opt_.approach_speed;
  } else {
    return;  // grasp, release: the grasping agent's; the platform stands still
  }
  const Pose2 at = platform_->pose(now);
  if (std::hypot(at.x - x, at.y - y) < 0.01) return;
  platform_->go_to(now, x, y, speed);
  ++goals_;
  if (opt_.on_drive)
    if (auto drives = platform_->drives(); !drives.empty()) opt_.on_drive(drives.back().first, drives.back().second);
}

void Navigation::status(nlohmann::json& out) const {
  out["frames"] = frames_;
  out["refused"] = refused_;
  out["moved_set"] = moved_set_;
  out["moved_cleared"] = moved_cleared_;
  if (opt_.follow_plan) out["goals"] = goals_;
  if (opt_.measure_humans) probe_.to_json(out["humans_latency"]);
}

}  // namespace quiver::agents::inline apps::agm
