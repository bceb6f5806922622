// ReplicaBridge: two groups of replicas (two robots) joined through a third (the team network) by
// one gateway per robot, each holding a replica on each side.
#include "quiver/agents/replica/replication/bridge.h"

#include <gtest/gtest.h>

#include "test_net.h"

namespace quiver::agents {
namespace {

// Robot A: agent a1 (1) and gateway side ga (10); the team: ta (11) and tb (21); robot B: gateway
// side gb (20) and agent b1 (2). Gateway A bridges ga and ta, gateway B gb and tb.
struct Team {
  Net robot_a, team, robot_b;
  int a1, ga, ta, tb, gb, b1;
  std::unique_ptr<ReplicaBridge> bridge_a, bridge_b;
  Team() {
    a1 = robot_a.add(1);
    ga = robot_a.add(10);
    ta = team.add(11);
    tb = team.add(21);
    gb = robot_b.add(20);
    b1 = robot_b.add(2);
    bridge_a = std::make_unique<ReplicaBridge>(*robot_a.nodes[ga].rep, *team.nodes[ta].rep);
    bridge_b = std::make_unique<ReplicaBridge>(*robot_b.nodes[gb].rep, *team.nodes[tb].rep);
    step(200'000'000);
  }
  Graph& g(Net& n, int i) { return *n.nodes[i].g; }
  Replicator& r(Net& n, int i) { return *n.nodes[i].rep; }
  // Time passes alike on the three networks; the gateways pump after each round.
  void step(std::int64_t ns, int rounds = 20) {
    for (int k = 0; k < rounds; ++k) {
      for (Net* n : {&robot_a, &team, &robot_b}) n->advance(ns / rounds, 1);
      bridge_a->pump(team.now);
      bridge_b->pump(team.now);
      for (Net* n : {&robot_a, &team, &robot_b}) n->pump();
    }
  }
  bool converged() {
    const auto d = g(robot_a, a1).digest();
    return g(robot_a, ga).digest() == d && g(team, ta).digest() == d && g(team, tb).digest() == d &&
           g(robot_b, gb).digest() == d && g(robot_b, b1).digest() == d;
  }
  std::uint64_t equivocations() {
    std::uint64_t n = 0;
    for (Net* net : {&robot_a, &team, &robot_b})
      for (auto& node : net->nodes) n += node.rep->stats().equivocations + node.rep->stats().rejected;
    return n;
  }
};

TEST(ReplicaBridgeTest, AChangeCrossesToTheOtherRobotUnderItsOwnOriginAndNumber) {
  Team t;
  const PeerId origin = t.g(t.robot_a, t.a1).replica();
  add_node(t.g(t.robot_a, t.a1), "mug");
  t.step(100'000'000);
  EXPECT_TRUE(t.g(t.robot_b, t.b1).find_node("mug").has_value());
  EXPECT_TRUE(t.r(t.robot_b, t.b1).applied().contains(origin, 1));
  EXPECT_TRUE(t.converged());
  EXPECT_EQ(t.bridge_a->stats().deltas_to[1], 1u);  // into the team
  EXPECT_EQ(t.bridge_b->stats().deltas_to[0], 1u);  // into robot B
  // Nothing came back: robot A's gateway side holds it from a1 only.
  EXPECT_EQ(t.bridge_a->stats().deltas_to[0], 0u);
  EXPECT_EQ(t.equivocations(), 0u);
  // b1 never heard a1: the change reached it through two gateways.
  EXPECT_FALSE(t.r(t.robot_b, t.b1).peer_known(origin));
}

TEST(ReplicaBridgeTest, RobotsWorkAloneWhileTheTeamNetworkIsDownAndConvergeAfter) {
  Team t;
  t.team.drop = [](const Packet&) { return true; };
  add_node(t.g(t.robot_a, t.a1), "a-side");
  add_node(t.g(t.robot_b, t.b1), "b-side");
  t.step(1'000'000'000);
  EXPECT_EQ(t.g(t.robot_a, t.ga).digest(), t.g(t.robot_a, t.a1).digest());
  EXPECT_EQ(t.g(t.robot_b, t.gb).digest(), t.g(t.robot_b, t.b1).digest());
  EXPECT_NE(t.g(t.robot_a, t.a1).digest(), t.g(t.robot_b, t.b1).digest());
  t.team.drop = nullptr;
  for (int i = 0; i < 100 && !t.converged(); ++i) t.step(100'000'000, 5);
  EXPECT_TRUE(t.converged());
  EXPECT_TRUE(t.g(t.robot_b, t.b1).find_node("a-side").has_value());
  EXPECT_TRUE(t.g(t.robot_a, t.a1).find_node("b-side").has_value());
  EXPECT_EQ(t.equivocations(), 0u);
}

TEST(ReplicaBridgeTest, WhatOneSideHeldBeforeTheBridgeIsAdoptedByTheOther) {
  Net robot, team;
  const int a1 = robot.add(1), ga = robot.add(10), ta = team.add(11), tb = team.add(21);
  for (int i = 0; i < 5; ++i) add_node(*robot.nodes[a1].g, "n" + std::to_string(i));
  robot.advance(500'000'000);
  team.advance(500'000'000);
  ASSERT_EQ(robot.nodes[ga].g->node_count(), 5u);
  ASSERT_EQ(team.nodes[tb].g->node_count(), 0u);
  ReplicaBridge bridge(*robot.nodes[ga].rep, *team.nodes[ta].rep);
  EXPECT_FALSE(bridge.even());
  bridge.pump(team.now);
  EXPECT_EQ(bridge.stats().states_to[1], 1u);
  EXPECT_TRUE(bridge.even());
  for (int i = 0; i < 20 && team.nodes[tb].g->digest() != robot.nodes[a1].g->digest(); ++i) {
    team.advance(100'000'000, 2);
    robot.advance(100'000'000, 2);
    bridge.pump(team.now);
  }
  EXPECT_EQ(team.nodes[tb].g->digest(), robot.nodes[a1].g->digest());
  EXPECT_EQ(team.nodes[tb].rep->stats().equivocations, 0u);
}

// Which robot and which agent each origin is crosses the gateways (kBehind beats): robot B's
// viewer names robot A's agent "navigation" on robot "A" (the inspector's and timeline's writer),
// lists robot A as reachable while the team link is up, and no longer once it is cut.
TEST(ReplicaBridgeTest, EveryRobotKnowsWhichRobotAndAgentEachOriginIs) {
  Net robot_a, team, robot_b;
  const auto named = [](const char* name, ReplicatorOptions o = {}) {
    o.name = name;
    return o;
  };
  ReplicatorOptions ga_opt, gb_opt;
  ga_opt.gateway = gb_opt.gateway = true;
  ga_opt.robot = "A";
  gb_opt.robot = "B";
  const int nav = robot_a.add(fnv1a64("navigation"), named("navigation"));
  // A name with a line break (any UTF-8 is a name) must not cost the others theirs.
  const int odd = robot_a.add(fnv1a64("two\nlines"), named("two\nlines"));
  const int ga = robot_a.add(10, named("A-gateway", ga_opt)), ta = team.add(11, named("A-gateway.team", ga_opt));
  const int tb = team.add(21, named("B-gateway.team", gb_opt)), gb = robot_b.add(20, named("B-gateway", gb_opt));
  ReplicatorOptions viewer_opt;
  viewer_opt.observer = true;
  const int viewer = robot_b.add(fnv1a64("quiver-view"), named("quiver-view", viewer_opt));
  const int b1 = robot_b.add(fnv1a64("rooms"), named("rooms"));
  ReplicaBridge bridge_a(*robot_a.nodes[ga].rep, *team.nodes[ta].rep);
  ReplicaBridge bridge_b(*robot_b.nodes[gb].rep, *team.nodes[tb].rep);
  const auto step = [&](std::int64_t ns) {
    for (int k = 0; k < 20; ++k) {
      for (Net* n : {&robot_a, &team, &robot_b}) n->advance(ns / 20, 1);
      bridge_a.pump(team.now);
      bridge_b.pump(team.now);
      for (Net* n : {&robot_a, &team, &robot_b}) n->pump();
    }
  };
  step(1'000'000'000);
  add_node(*robot_a.nodes[nav].g, "mug");
  step(200'000'000);
  const Replicator& v = *robot_b.nodes[viewer].rep;
  const PeerId nav_id = robot_a.nodes[nav].g->replica();
  ASSERT_TRUE(robot_b.nodes[viewer].g->find_node("mug").has_value());
  EXPECT_FALSE(v.peer_known(nav_id)) << "the viewer never heard it: it learned of it through two gateways";
  EXPECT_EQ(v.name_of(nav_id), "navigation");
  EXPECT_EQ(v.robot_of(nav_id), "A");
  EXPECT_EQ(v.robot_here(), "B");
  EXPECT_EQ(v.robot_of(robot_b.nodes[b1].g->replica()), "B");
  EXPECT_EQ(v.robot_of(robot_b.nodes[viewer].g->replica()), "B");
  std::vector<Member> remote = v.remote_members();
  ASSERT_EQ(remote.size(), 2u);
  const PeerId odd_id = robot_a.nodes[odd].g->replica();
  if (remote[0].id == odd_id) std::swap(remote[0], remote[1]);
  EXPECT_EQ(remote[1].robot, "A") << "named unknown, but on robot A";
  EXPECT_EQ(remote[0].id, nav_id);
  EXPECT_EQ(remote[0].name, "navigation");
  EXPECT_EQ(remote[0].robot, "A");
  EXPECT_EQ(remote[0].via, robot_b.nodes[gb].g->replica());
  // And the other way: robot A's agent knows robot B's.
  EXPECT_EQ(robot_a.nodes[nav].rep->robot_of(robot_b.nodes[b1].g->replica()), "B");
  EXPECT_EQ(robot_a.nodes[nav].rep->name_of(robot_b.nodes[b1].g->replica()), "rooms");
  // The team link cut: robot A is no longer reachable from B (its gateway declared A's gone),
  // but the writer of what A wrote is still named.
  team.drop = [](const Packet&) { return true; };
  step(5'000'000'000);
  EXPECT_TRUE(v.remote_members().empty());
  EXPECT_EQ(v.robot_of(nav_id), "A");
  EXPECT_EQ(v.name_of(nav_id), "navigation");
}

TEST(ReplicaBridgeTest, RelayRefusesWhatNamesNoOriginOrInterval) {
  Net n;
  const int a = n.add(1);
  DeltaMsg m;
  EXPECT_FALSE(n.nodes[a].rep->relay(m).ok());
  m.origin = n.nodes[a].g->replica();  // its own
  m.lo = m.hi = 1;
  m.payload = std::make_shared<const std::vector<std::uint8_t>>();
  EXPECT_FALSE(n.nodes[a].rep->relay(m).ok());
}

}  // namespace
}  // namespace quiver::agents
