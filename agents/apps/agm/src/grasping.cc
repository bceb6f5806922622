// The grasping agent: sets reach from the platform's pose and grasps and releases objects,
// never while the platform drives.
#include "quiver/agents/apps/agm/grasping.h"

#include <map>
#include <nlohmann/json.hpp>

#include "quiver/agents/apps/agm/agm_schema.h"
#include "quiver/kinematics/collision_scene.h"

namespace quiver::agents::inline apps::agm {

using graph::NodeId;
using graph::Symbol;
using graph::Value;

const char* GraspEvent::name() const {
  switch (kind) {
    case Kind::kReach:
      return "reach";
    case Kind::kNoReach:
      return "noReach";
    case Kind::kStarted:
      return "started";
    case Kind::kPaused:
      return "paused";
    case Kind::kGrasped:
      return "grasped";
    case Kind::kReleased:
      return "released";
    case Kind::kMissed:
      return "missed";
  }
  return "?";
}

namespace {

// The grasp of one object, as an action of the DSR loop.
class GraspAction final : public Action {
 public:
  explicit GraspAction(Grasping& agent) : Action("grasp"), agent_(agent) {}

  std::vector<Match> find(AgentContext& ctx) override {
    std::vector<Match> out;
    graph::Graph& g = ctx.graph();
    const NodeId robot = node_id(g, agent_.options().names.robot);
    if (robot.is_null() || !agent_.platform_still(ctx)) return out;
    for (const graph::EdgeKey& e : g.edges_from(robot, edge::kFetch))
      if (ready(g, robot, e.to) && !resting(e.to, ctx.now()))
        out.push_back(Match{g.name_of(e.to), {{"robot", robot}, {"object", e.to}}});
    if (const NodeId o = planned(g); !o.is_null() && !g.has_edge(robot, o, edge::kFetch) &&
                                     ready(g, robot, o) && !resting(o, ctx.now()) &&
                                     g.edges_from(robot, edge::kCarrying).empty())
      out.push_back(Match{g.name_of(o), {{"robot", robot}, {"object", o}}});
    return out;
  }

  bool holds(AgentContext& ctx, const Match& m) override {
    const graph::Graph& g = ctx.graph();
    return (g.has_edge(m.at("robot"), m.at("object"), edge::kFetch) ||
            planned(g) == m.at("object")) &&
           g.has_edge(m.at("robot"), m.at("object"), edge::kReach) && agent_.platform_still(ctx);
  }

  std::optional<LockNeed> lock(AgentContext&, const Match& m) override {
    if (!agent_.options().lock_objects) return std::nullopt;
    return LockNeed{m.at("object"), 1};
  }

  Status start(AgentContext& ctx, const Match& m) override {
    graph::Transaction tx = ctx.graph().begin();
    const std::int64_t now = ctx.now();
    Status s = tx.insert_edge(m.at("robot"), m.at("object"), Symbol(edge::kGrasping),
                              {{Symbol("started_ns"), Value(now)}});
    if (s.ok()) {
      if (auto c = tx.commit(); !c.ok()) s = c.error();
    }
    if (!s.ok()) return s;
    started_[m.key] = now;
    agent_.note({GraspEvent::Kind::kStarted, m.key, now});
    return {};
  }

  Progress process(AgentContext& ctx, const Match& m) override {
    // Checked again right before the grasp closes: nothing may have moved since the last look.
    if (!holds(ctx, m)) return Progress::kFailed;
    if (ctx.now() - started_[m.key] < agent_.options().grasp_ns) return Progress::kRunning;
    // The hand closes: on nothing if another robot holds the object.
    const GraspingOptions& o = agent_.options();
    if (o.custody && !o.custody->take(m.key, o.names.robot)) {
      missed_[m.at("object")] = ctx.now();
      agent_.note({GraspEvent::Kind::kMissed, m.key, ctx.now()});
      return Progress::kFailed;
    }
    return Progress::kDone;
  }

  Status finish(AgentContext& ctx, const Match& m) override {
    graph::Graph& g = ctx.graph();
    const NodeId robot = m.at("robot"), object = m.at("object"),
                 gripper = node_id(g, agent_.options().names.gripper);
    const std::int64_t now = ctx.now();
    graph::Transaction tx = g.begin();
    Status s = tx.delete_edge(robot, object, Symbol(edge::kGrasping));
    if (s.ok() && g.has_edge(robot, object, edge::kFetch))
      s = tx.delete_edge(robot, object, Symbol(edge::kFetch));
    // Off the table (clean the table: graspFromTable).
    for (const graph::EdgeKey& on : g.edges_from(object, edge::kOn))
      if (s.ok()) s = tx.delete_edge(object, on.to, Symbol(edge::kOn));
    if (s.ok())
      s = tx.insert_edge(
          robot, object, Symbol(edge::kCarrying),
          {{Symbol("started_ns"), Value(started_[m.key])}, {Symbol("finished_ns"), Value(now)}});
    // The object now hangs from the gripper (held at its centre).
    if (s.ok() && !gripper.is_null()) s = tx.set_rt(gripper, object, graph::Pose{}, now);
    if (s.ok()) {
      if (auto c = tx.commit(); !c.ok()) s = c.error();
    }
    if (!s.ok()) {
      // The graph refuses what the hand did (the object left the table meanwhile): let go.
      if (agent_.options().custody) agent_.options().custody->put(m.key, agent_.options().names.robot);
      return s;
    }
    agent_.note({GraspEvent::Kind::kGrasped, m.key, now});
    return {};
  }

  void cancel(AgentContext& ctx, const Match& m, CancelReason why) override {
    graph::Graph& g = ctx.graph();
    if (g.has_edge(m.at("robot"), m.at("object"), edge::kGrasping)) {
      graph::Transaction tx = g.begin();
      if (tx.delete_edge(m.at("robot"), m.at("object"), Symbol(edge::kGrasping)).ok())
        (void)tx.commit();
    }
    ctx.log(std::string("grasp of ") + m.key + " paused: " + to_string(why));
    agent_.note({GraspEvent::Kind::kPaused, m.key, ctx.now()});
  }

 private:
  // The object the plan's next step asks to grasp (follow_plan), or the null id.
  NodeId planned(const graph::Graph& g) const {
    if (!agent_.options().follow_plan) return {};
    auto step = next_plan_step(g, agent_.options().names.plan);
    return step && step->rule == "grasp" ? step->at("o") : NodeId{};
  }
  // Missed lately (another robot holds it): left alone for a while.
  bool resting(NodeId object, std::int64_t now) const {
    auto it = missed_.find(object);
    return it != missed_.end() && now - it->second < agent_.options().retry_ns;
  }
  static bool ready(const graph::Graph& g, NodeId robot, NodeId object) {
    return g.has_edge(robot, object, edge::kReach) && !g.has_edge(robot, object, edge::kCarrying);
  }
  Grasping& agent_;
  std::map<std::string, std::int64_t> started_;
  std::map<NodeId, std::int64_t> missed_;
};

}  // namespace

Grasping::Grasping(GraspingOptions o, std::string name)
    : Agent(std::move(name)), opt_(std::move(o)) {
  set_grammar_text(std::string(role_grammar("grasping")), "grasping.aggl");
  add_action(std::make_unique<GraspAction>(*this));
}

Grasping::~Grasping() = default;

void Grasping::setup(AgentContext& ctx) {
  frames_ = std::make_unique<kinematics::FrameTree>(ctx.graph());
  scene_ = std::make_unique<kinematics::CollisionScene>(*frames_);
  if (opt_.measure_humans) probe_.attach(*this, ctx);
  ctx.every(static_cast<std::int64_t>(1e9 / opt_.rate_hz), [this, &ctx] {
    measure(ctx);
    if (opt_.follow_plan) release(ctx);
  });
}

void Grasping::teardown(AgentContext&) {
  scene_.reset();
  frames_.reset();
}

bool Grasping::platform_still(AgentContext& ctx) const {
  const graph::Graph& g = ctx.graph();
  const NodeId robot = node_id(g, opt_.names.robot);
  if (robot.is_null() || g.has_edge(robot, robot, edge::kMoved)) return false;
  auto X_WR = g.rt_edge(robot);
  return X_WR && ctx.now() - X_WR->stamp <= opt_.fresh_ns;
}

void Grasping::note(const GraspEvent& e) {
  if (e.kind == GraspEvent::Kind::kPaused) ++pauses_;
  if (e.kind == GraspEvent::Kind::kGrasped) ++grasps_;
  if (e.kind == GraspEvent::Kind::kReleased) ++releases_;
  if (opt_.on_event) opt_.on_event(e);
}

void Grasping::measure(AgentContext& ctx) {
  graph::Graph& g = ctx.graph();
  const NodeId robot = node_id(g, opt_.names.robot), gripper = node_id(g, opt_.names.gripper);
  if (robot.is_null() || gripper.is_null() || !scene_) return;
  const auto X_WR = g.rt_edge(robot);
  const std::int64_t stamp = X_WR ? X_WR->stamp : 0;
  std::vector<std::pair<NodeId, bool>> tracked;  // object, reach now
  for (const graph::EdgeKey& e : g.edges_from(robot, edge::kReach))
    tracked.emplace_back(e.to, true);
  for (const graph::EdgeKey& e : g.edges_from(robot, edge::kNoReach))
    if (!g.has_edge(robot, e.to, edge::kReach)) tracked.emplace_back(e.to, false);
  for (auto [object, reach] : tracked) {
    auto d = scene_->distance(gripper, object);
    if (!d.ok()) continue;
    const double dist = d->distance;
    const bool now_reach = reach ? dist <= opt_.reach_off_m : dist < opt_.reach_on_m;
    if (now_reach == reach) continue;
    graph::Transaction tx = g.begin();
    const char* gone = now_reach ? edge::kNoReach : edge::kReach;
    const char* made = now_reach ? edge::kReach : edge::kNoReach;
    Status s =
        g.has_edge(robot, object, gone) ? tx.delete_edge(robot, object, Symbol(gone)) : Status{};
    if (s.ok() && !g.has_edge(robot, object, made))
      s = tx.insert_edge(robot, object, Symbol(made),
                         {{Symbol("distance"), Value(dist)},
                          {Symbol("stamp_ns"), Value(stamp)},
                          {Symbol("committed_ns"), Value(ctx.now())}});
    if (s.ok()) {
      if (auto c = tx.commit(); !c.ok()) s = c.error();
    }
    if (!s.ok()) {
      ++refused_;
      ctx.log("reach of " + g.name_of(object) + " refused: " + s.error().to_string());
      continue;
    }
    ++reach_changes_;
    note({now_reach ? GraspEvent::Kind::kReach : GraspEvent::Kind::kNoReach, g.name_of(object),
          ctx.now(), dist, stamp});
  }
}

void Grasping::release(AgentContext& ctx) {
  graph::Graph& g = ctx.graph();
  auto step = next_plan_step(g, opt_.names.plan);
  if (!step || step->rule != "release") return;
  const NodeId robot = node_id(g, opt_.names.robot), object = step->at("o"),
               gripper = node_id(g, opt_.names.gripper), world = node_id(g, node::kWorld);
  if (robot.is_null() || object.is_null() || world.is_null() ||
      !g.has_edge(robot, object, edge::kCarrying) || !platform_still(ctx))
    return;
  const std::int64_t now = ctx.now();
  graph::Pose X_WO;
  if (auto p = gripper.is_null() ? std::nullopt : world_position(g, gripper)) X_WO.translation = *p;
  graph::Transaction tx = g.begin();
  Status s = tx.delete_edge(robot, object, Symbol(edge::kCarrying));
  if (s.ok()) s = tx.set_rt(world, object, X_WO, now);
  if (s.ok()) {
    if (auto c = tx.commit(); !c.ok()) s = c.error();
  }
  if (!s.ok()) {
    ++refused_;
    ctx.log("release of " + g.name_of(object) + " refused: " + s.error().to_string());
    return;
  }
  if (opt_.custody) opt_.custody->put(g.name_of(object), opt_.names.robot);
  note({GraspEvent::Kind::kReleased, g.name_of(object), now});
}

void Grasping::status(nlohmann::json& out) const {
  out["reach_changes"] = reach_changes_;
  out["grasps"] = grasps_;
  out["pauses"] = pauses_;
  out["refused"] = refused_;
  if (opt_.follow_plan) out["releases"] = releases_;
  if (opt_.measure_humans) probe_.to_json(out["humans_latency"]);
}

}  // namespace quiver::agents::inline apps::agm
