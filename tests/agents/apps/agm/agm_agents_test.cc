// The AGM scenario's agents (agents/apps/agm) one at a time, each in an AgentRuntime driven by hand
// (time, ticks) on the AGM world, with the changes of the other agents merged in from a second
// replica ("the others"): the platform's route, the room geometry, changeRoom at crossings (and
// with a carried object), reach with hysteresis from FCL distances, the grasp paused while the
// platform moves or its pose is stale, movedInLastSeconds from odometry, the latency probe.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "quiver/agents/apps/agm/agm_roles.h"
#include "quiver/agents/apps/agm/agm_schema.h"
#include "quiver/agents/rules/grammar/grammar.h"
#include "quiver/agents/runtime/engine/engine.h"
#include "quiver/graph/world_file.h"
#include "quiver/base/hash.h"

namespace quiver::agents::agm {
namespace {

using graph::NodeId;
using graph::Symbol;
using graph::Value;
constexpr std::int64_t kMs = 1'000'000;
constexpr std::int64_t kSec = 1'000'000'000;

// One agent under test on its own replica, and a second replica whose commits are merged into it.
struct Rig {
  explicit Rig(Agent& a)
      : g(graph::ReplicaId{fnv1a64(a.name()), 1}), others(graph::ReplicaId{fnv1a64("others"), 1}) {
    auto seed = graph::world_seed(world_json(), "agm.json");
    EXPECT_TRUE(seed.ok());
    g.merge(seed->delta);
    others.merge(seed->delta);
    others.set_delta_sink([this](const graph::GraphDelta& d) { g.merge(d); });
    g.set_delta_sink([this](const graph::GraphDelta& d) { others.merge(d); });
    RuntimeOptions o;
    o.clock = [this] { return now; };
    o.log = [](std::string_view line) {
      std::printf("  agent: %.*s\n", static_cast<int>(line.size()), line.data());
    };
    rt = std::make_unique<AgentRuntime>(a, g, nullptr, o);
    Status s = rt->start();
    EXPECT_TRUE(s.ok()) << s.error().to_string();
  }
  NodeId id(const char* name) const { return node_id(g, name); }
  // The robot's pose as the navigation agent would publish it (on the other replica).
  void pose(double x, double y) {
    auto tx = others.begin();
    graph::Pose X;
    X.translation = {x, y, 0};
    ASSERT_TRUE(tx.set_rt(node_id(others, "world"), node_id(others, "robot"), X, now).ok());
    ASSERT_TRUE(tx.commit().ok());
    rt->pump();
  }
  void edge(const char* from, const char* to, const char* type, bool insert) {
    auto tx = others.begin();
    NodeId a = node_id(others, from), b = node_id(others, to);
    ASSERT_TRUE(
        (insert ? tx.insert_edge(a, b, Symbol(type)) : tx.delete_edge(a, b, Symbol(type))).ok());
    ASSERT_TRUE(tx.commit().ok());
    rt->pump();
  }
  // Advances time in host ticks of 10 ms; `each` runs before every tick (e.g. fresh poses).
  void run_for(std::int64_t ns, const std::function<void()>& each = {}) {
    const std::int64_t end = now + ns;
    while (now < end) {
      now += 10 * kMs;
      if (each) each();
      rt->tick();
    }
  }
  bool has(const char* from, const char* to, const char* type) const {
    return g.has_edge(id(from), id(to), type);
  }
  std::string room() const {
    auto r = room_of(g, id("robot"));
    return r ? g.name_of(*r) : "";
  }

  std::int64_t now = 5 * kSec;
  graph::Graph g, others;
  std::unique_ptr<AgentRuntime> rt;
};

TEST(AgmPlatform, FollowsTheRouteWaitsForTheReleaseAndKnowsWhenItMoved) {
  Platform p(default_route(), default_start());
  EXPECT_FALSE(p.started());
  p.start(0);
  EXPECT_DOUBLE_EQ(p.pose(0).x, 1.0);
  EXPECT_FALSE(p.moved_between(0, 2 * kSec)) << "it stands still for 2 s first";
  EXPECT_NEAR(p.pose(8 * kSec).x, 4.0, 1e-9) << "0.5 m/s from x = 1 at t = 2 s";
  EXPECT_TRUE(p.moving(5 * kSec));
  EXPECT_NEAR(p.pose(19 * kSec).x, 8.25, 1e-9);
  EXPECT_NEAR(p.pose(21 * kSec).x, 8.15, 1e-9) << "the nudge back";
  EXPECT_TRUE(p.waiting(22 * kSec));
  EXPECT_TRUE(p.moved_between(21 * kSec, 30 * kSec)) << "forward again at 21.4 s";
  EXPECT_FALSE(p.moved_between(22 * kSec, 30 * kSec)) << "waiting for the grasp";
  EXPECT_NEAR(*p.end_time(), 75.3e9, 1e3) << "unreleased: the wait times out after 40 s";
  EXPECT_FALSE(p.release(15 * kSec)) << "not waiting then";
  EXPECT_TRUE(p.release(22 * kSec));
  EXPECT_FALSE(p.release(22 * kSec + 1)) << "released once";
  EXPECT_NEAR(*p.end_time(), 35.5e9, 1e3);
  EXPECT_TRUE(p.moving(30 * kSec));
  EXPECT_NEAR(p.pose(36 * kSec).x, 2.0, 1e-9);
  EXPECT_TRUE(p.finished(36 * kSec));
  ASSERT_EQ(p.drives().size(), 5u);
}

TEST(AgmWorld, RoomsTileTheWayAndWallsBelongToOneRoom) {
  graph::Graph g(graph::ReplicaId{1, 1});
  auto seed = graph::world_seed(world_json(), "agm.json");
  ASSERT_TRUE(seed.ok()) << seed.error().to_string();
  g.merge(seed->delta);
  auto name = [&](double x, double y) {
    auto r = room_at(g, x, y);
    return r ? g.name_of(*r) : std::string("none");
  };
  EXPECT_EQ(name(3.99, 2), "kitchen");
  EXPECT_EQ(name(4.0, 2), "corridor");
  EXPECT_EQ(name(6.0, 2), "livingroom");
  EXPECT_EQ(name(5.0, 0.5), "none") << "beside the corridor";
  auto path = room_path(g, node_id(g, "kitchen"), node_id(g, "livingroom"));
  ASSERT_EQ(path.size(), 3u);
  EXPECT_EQ(g.name_of(path[1]), "corridor");
  for (const auto& role : role_names()) {
    auto grammar = parse_grammar(role_grammar(role), role + ".aggl");
    EXPECT_TRUE(grammar.ok()) << role << ": " << grammar.error().to_string();
  }
}

TEST(AgmRooms, ChangeRoomAtTheCrossingAlongTransitableRoomsCarryingWhatTheRobotHolds) {
  std::vector<RoomChange> seen;
  RoomsOptions o;
  o.on_change = [&](const RoomChange& c) { seen.push_back(c); };
  Rooms rooms(o);
  Rig rig(rooms);
  rig.pose(3.98, 2.0);
  EXPECT_EQ(rig.room(), "kitchen");
  EXPECT_TRUE(seen.empty());
  rig.pose(4.01, 2.0);
  EXPECT_EQ(rig.room(), "corridor") << "at the first pose past the limit";
  ASSERT_EQ(seen.size(), 1u);
  EXPECT_EQ(seen[0].from, "kitchen");
  EXPECT_DOUBLE_EQ(seen[0].x, 4.01);
  EXPECT_EQ(seen[0].stamp_ns, rig.now);
  const graph::EdgeKey in{rig.id("robot"), rig.id("corridor"), Symbol("in")};
  EXPECT_DOUBLE_EQ(*rig.g.edge_attr(in, "x")->get_if<double>(), 4.01);
  rig.pose(2.0, 2.0);  // back in the kitchen
  rig.edge("robot", "mug", "carrying", true);
  // The mug is in the living room; carried from the kitchen it would be a contradiction the rule
  // leaves alone: only objects in the room the robot leaves move with it.
  rig.pose(7.0, 2.0);  // one jump over the corridor: two rule applications, in order
  ASSERT_EQ(seen.size(), 4u);
  EXPECT_EQ(seen[2].to, "corridor");
  EXPECT_EQ(seen[3].to, "livingroom");
  EXPECT_EQ(rig.room(), "livingroom");
  rig.pose(5.0, 2.0);
  EXPECT_EQ(rig.room(), "corridor");
  auto mug_room = room_of(rig.g, rig.id("mug"));
  ASSERT_TRUE(mug_room);
  EXPECT_EQ(rig.g.name_of(*mug_room), "corridor") << "the carried mug changed room with the robot";
  nlohmann::json st;
  rooms.status(st);
  EXPECT_EQ(st["refused"], 0) << "every change was one application of changeRoom";
}

TEST(AgmGrasping, ReachFollowsFclDistanceWithHysteresis) {
  for (bool hysteresis : {true, false}) {
    std::vector<GraspEvent> events;
    GraspingOptions o;
    if (!hysteresis) o.reach_off_m = o.reach_on_m;  // the control: one threshold
    o.on_event = [&](const GraspEvent& e) { events.push_back(e); };
    Grasping grasping(o);
    Rig rig(grasping);
    rig.edge("robot", "mug", "fetch", false);  // no grasp in this test
    auto at = [&](double x) { rig.run_for(200 * kMs, [&] { rig.pose(x, 2.0); }); };
    at(8.0);  // gripper 0.27 m from the mug
    EXPECT_TRUE(rig.has("robot", "mug", "noReach"));
    at(8.25);  // 0.02 m
    ASSERT_TRUE(rig.has("robot", "mug", "reach"));
    EXPECT_FALSE(rig.has("robot", "mug", "noReach"));
    const double d =
        *rig.g.edge_attr({rig.id("robot"), rig.id("mug"), Symbol("reach")}, "distance")
             ->get_if<double>();
    EXPECT_NEAR(d, 0.02, 1e-3) << "FCL's sphere-cylinder distance";
    at(8.15);  // 0.12 m: between the thresholds
    EXPECT_EQ(rig.has("robot", "mug", "reach"), hysteresis)
        << (hysteresis ? "kept by hysteresis" : "one threshold flips");
    at(8.25);
    at(8.05);  // 0.22 m
    EXPECT_TRUE(rig.has("robot", "mug", "noReach"));
    EXPECT_EQ(events.size(), hysteresis ? 2u : 4u)
        << "reach, noReach; without hysteresis the nudge flips it twice more";
  }
}

TEST(AgmGrasping, GraspPausesWhileThePlatformMovesOrItsPoseIsStaleThenCompletes) {
  std::vector<GraspEvent> events;
  GraspingOptions o;
  o.on_event = [&](const GraspEvent& e) { events.push_back(e); };
  Grasping grasping(o);
  Rig rig(grasping);
  bool localizing = true;
  auto fresh = [&] {
    if (localizing && rig.now % (30 * kMs) == 0) rig.pose(8.25, 2.0);
  };
  rig.run_for(500 * kMs, fresh);
  EXPECT_TRUE(rig.has("robot", "mug", "grasping")) << "in reach, still, fresh pose: the grasp runs";
  rig.edge("robot", "robot", "movedInLastSeconds", true);
  EXPECT_FALSE(rig.has("robot", "mug", "grasping")) << "paused as soon as the platform moves";
  // The grammar refuses a grasp while the robot moves (whatever the agent's code does).
  {
    auto tx = rig.g.begin();
    (void)tx.insert_edge(rig.id("robot"), rig.id("mug"), Symbol("grasping"));
    EXPECT_FALSE(tx.commit().ok());
  }
  rig.run_for(3 * kSec, fresh);
  EXPECT_FALSE(rig.has("robot", "mug", "carrying"));
  EXPECT_FALSE(rig.has("robot", "mug", "grasping"));
  rig.edge("robot", "robot", "movedInLastSeconds", false);
  rig.run_for(700 * kMs, fresh);
  ASSERT_TRUE(rig.has("robot", "mug", "grasping")) << "started again once still";
  localizing = false;  // cut off from localization: no fresh pose
  rig.run_for(400 * kMs);
  EXPECT_FALSE(rig.has("robot", "mug", "grasping")) << "a stale pose pauses it too";
  localizing = true;
  rig.run_for(1400 * kMs, fresh);
  EXPECT_FALSE(rig.has("robot", "mug", "carrying")) << "1.5 s of uninterrupted grasping are needed";
  rig.run_for(400 * kMs, fresh);
  ASSERT_TRUE(rig.has("robot", "mug", "carrying"));
  EXPECT_FALSE(rig.has("robot", "mug", "fetch"));
  EXPECT_FALSE(rig.has("robot", "mug", "grasping"));
  EXPECT_EQ(rig.g.rt_parent(rig.id("mug")), rig.id("gripper")) << "the mug hangs from the gripper";
  int started = 0, paused = 0, grasped = 0;
  for (const auto& e : events) {
    started += e.kind == GraspEvent::Kind::kStarted;
    paused += e.kind == GraspEvent::Kind::kPaused;
    grasped += e.kind == GraspEvent::Kind::kGrasped;
  }
  EXPECT_EQ(started, 3);
  EXPECT_EQ(paused, 2);
  EXPECT_EQ(grasped, 1);
  EXPECT_TRUE(rig.others.has_edge(rig.id("robot"), rig.id("mug"), "carrying")) << "published";
}

TEST(AgmNavigation, PublishesPosesAndMovedInLastSecondsFromOdometryAndWaitsForTheGrasp) {
  using K = Leg::Kind;
  auto platform = std::make_shared<Platform>(std::vector<Leg>{{K::kStand, 0, 0, 0, 0.5},
                                                              {K::kDrive, 2.0, 2.0, 1.0, 0},
                                                              {K::kWait, 0, 0, 0, 10},
                                                              {K::kDrive, 1.0, 2.0, 1.0, 0}},
                                             default_start());
  NavigationOptions o;
  o.quiet_when_done = true;
  Navigation nav(platform, o);
  Rig rig(nav);
  const std::int64_t t0 = platform->t0();
  EXPECT_EQ(t0, rig.now) << "started by setup()";
  rig.run_for(400 * kMs);
  EXPECT_FALSE(rig.has("robot", "robot", "movedInLastSeconds"));
  EXPECT_EQ(*rig.g.get<std::int64_t>(rig.id("robot"), "route_t0_ns"), t0);
  rig.run_for(200 * kMs);
  EXPECT_TRUE(rig.has("robot", "robot", "movedInLastSeconds")) << "driving since t0 + 0.5 s";
  rig.run_for(1400 * kMs);  // the drive ended at t0 + 1.5 s; now t0 + 2.0 s
  EXPECT_TRUE(rig.has("robot", "robot", "movedInLastSeconds")) << "moved within the last second";
  EXPECT_NEAR(rig.g.rt_edge(rig.id("robot"))->pose.translation[0], 2.0, 0.005)
      << "localization: jitter of 3 mm";
  rig.run_for(600 * kMs);
  EXPECT_FALSE(rig.has("robot", "robot", "movedInLastSeconds"))
      << "cleared a second after the drive";
  rig.run_for(3 * kSec);
  EXPECT_TRUE(platform->waiting(rig.now));
  rig.edge("robot", "mug", "carrying", true);
  rig.run_for(100 * kMs);
  EXPECT_FALSE(platform->waiting(rig.now)) << "released once the robot carries something";
  EXPECT_TRUE(rig.g.attr(rig.id("robot"), "route_release_ns"));
  rig.run_for(3 * kSec);
  EXPECT_TRUE(platform->finished(rig.now));
  EXPECT_FALSE(rig.has("robot", "robot", "movedInLastSeconds"));
  const auto stamp = rig.g.rt_edge(rig.id("robot"))->stamp;
  rig.run_for(500 * kMs);
  EXPECT_EQ(rig.g.rt_edge(rig.id("robot"))->stamp, stamp) << "quiet when done";
  nlohmann::json st;
  nav.status(st);
  EXPECT_EQ(st["refused"], 0);
  EXPECT_EQ(st["moved_set"], 2);
}

TEST(AgmPlatform, GoToAppendsDrivesFromIdle) {
  Platform p({}, default_start());
  EXPECT_FALSE(p.end_time().has_value());
  p.start(1 * kSec);
  EXPECT_TRUE(p.finished(1 * kSec)) << "no legs: idle from the start";
  p.go_to(3 * kSec, 3.0, 2.0, 1.0);  // 2 m at 1 m/s, from 3 s
  EXPECT_FALSE(p.moving(2 * kSec));
  EXPECT_TRUE(p.moving(4 * kSec));
  EXPECT_NEAR(p.pose(4 * kSec).x, 2.0, 1e-6);
  EXPECT_EQ(*p.end_time(), 5 * kSec);
  EXPECT_TRUE(p.finished(5 * kSec));
  EXPECT_NEAR(p.pose(9 * kSec).x, 3.0, 1e-9);
}

TEST(AgmPlan, NextStepFromThePlanNodeByAgmIdOrName) {
  graph::Graph g(graph::ReplicaId{7, 1});
  auto seed = graph::world_seed(embedded_file("clean-table.json"), "clean-table.json");
  ASSERT_TRUE(seed.ok()) << seed.error().to_string();
  g.merge(seed->delta);
  const NodeId plan = node_id(g, "plan");
  ASSERT_FALSE(plan.is_null());
  EXPECT_FALSE(next_plan_step(g)) << "no status yet";
  auto tx = g.begin();
  ASSERT_TRUE(tx.set(plan, "status", Value(std::string("executing"))).ok());
  ASSERT_TRUE(tx.set(plan, "next", Value(std::int64_t{1})).ok());
  ASSERT_TRUE(tx.set(plan, "steps", Value(std::string("changeRoom@{'a': '2', 'b': '3', 'r': '1'}\n"
                                                        "approach@{'o': '7', 'r': 'robot', 't': '5', 'x': '4'}\n")))
                  .ok());
  ASSERT_TRUE(tx.commit().ok());
  auto step = next_plan_step(g);
  ASSERT_TRUE(step);
  EXPECT_EQ(step->rule, "approach");
  EXPECT_EQ(step->at("o"), node_id(g, "mug2"));
  EXPECT_EQ(step->at("r"), node_id(g, "robot"));
  EXPECT_TRUE(step->at("nope").is_null());
  auto p = world_position(g, node_id(g, "gripper"));
  ASSERT_TRUE(p);
  EXPECT_NEAR((*p)[0], 1.35, 1e-9);
  EXPECT_NEAR((*p)[2], 0.81, 1e-9);
  // A step naming a node the graph lacks is no step.
  auto tx2 = g.begin();
  ASSERT_TRUE(tx2.set(plan, "next", Value(std::int64_t{0})).ok());
  ASSERT_TRUE(tx2.set(plan, "steps", Value(std::string("grasp@{'o': '99'}\n"))).ok());
  ASSERT_TRUE(tx2.commit().ok());
  EXPECT_FALSE(next_plan_step(g));
}

TEST(AgmLatencyProbe, PercentilesAndPooling) {
  LatencyProbe p;
  for (int ms = 1; ms <= 100; ++ms) p.record(ms * kMs);
  // Nearest rank (as bench_stats.h), reported at the upper edge of its 10 us bucket.
  EXPECT_NEAR(p.percentile_us(0.5), 51'010, 1);
  EXPECT_NEAR(p.percentile_us(0.99), 99'010, 1);
  EXPECT_DOUBLE_EQ(p.max_us(), 100'000);
  nlohmann::json j;
  p.to_json(j);
  LatencyProbe pooled;
  pooled.merge_json(j);
  pooled.record(2 * kSec);
  EXPECT_EQ(pooled.count(), 101u);
  EXPECT_DOUBLE_EQ(pooled.max_us(), 2'000'000);
  EXPECT_NEAR(pooled.percentile_us(0.5), 51'010, 1);
}

}  // namespace
}  // namespace quiver::agents::agm
