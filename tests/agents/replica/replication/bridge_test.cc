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
