// Translation of RoboComp CORTEX tests/synchronization/fake_network_tests.cpp onto Quiver, its
// cases about the network: basic delivery, drop + recovery, partition / rejoin, cold start, and
// edge synchronisation. They run replicas with their Replicators on the in-memory test network
// (tests/common/test_net.h), simulated time. Shared helpers and the mapping notes are in
// fake_network_fixture.h.

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "fake_network_fixture.h"
#include "test_net.h"

namespace quiver::cortex_tests {
namespace {

using agents::Net;
using graph::Pose;

constexpr std::int64_t kSecond = 1'000'000'000;

NodeId commit_robot(Graph& g, const std::string& name) {
  auto tx = g.begin();
  NodeId id = robot(tx, name);
  EXPECT_TRUE(tx.commit().ok());
  return id;
}

// ---------------------------------------------------------------------------------------------
// Basic delivery

// CORTEX fake_network_tests.cpp, "FakeNetwork: LWW insert propagates to peer". Class (a).
TEST(CortexFakeNetwork, LwwInsertPropagatesToPeer) {
  Net net;
  int a = net.add(1), b = net.add(2);
  net.pump();
  NodeId id = commit_robot(*net.nodes[a].g, "robot_a");
  net.pump();
  EXPECT_TRUE(net.nodes[a].g->has_node(id));
  EXPECT_TRUE(net.nodes[b].g->has_node(id));
}

// CORTEX fake_network_tests.cpp, "FakeNetwork: CRDT insert propagates to peer". Class (a); the
// same scenario as the LWW case (Quiver has one mode).
TEST(CortexFakeNetwork, CrdtInsertPropagatesToPeer) {
  Net net;
  int a = net.add(1), b = net.add(2);
  net.pump();
  NodeId id = commit_robot(*net.nodes[a].g, "robot_a");
  net.pump();
  EXPECT_TRUE(net.nodes[a].g->has_node(id));
  EXPECT_TRUE(net.nodes[b].g->has_node(id));
  EXPECT_EQ(net.nodes[b].g->name_of(id), "robot_a");
  EXPECT_EQ(level(*net.nodes[b].g, id), 0);
}

void bidirectional_inserts_converge() {
  Net net;
  int a = net.add(1), b = net.add(2);
  net.pump();
  NodeId ia = commit_robot(*net.nodes[a].g, "robot_a");
  NodeId ib = commit_robot(*net.nodes[b].g, "robot_b");
  net.pump();
  EXPECT_TRUE(net.nodes[a].g->has_node(ib));
  EXPECT_TRUE(net.nodes[b].g->has_node(ia));
  EXPECT_EQ(net.nodes[a].g->node_count(), net.nodes[b].g->node_count());
  EXPECT_EQ(net.nodes[a].g->node_count(), 2u);
}

// CORTEX fake_network_tests.cpp, "FakeNetwork: LWW bidirectional inserts converge". Class (a).
TEST(CortexFakeNetwork, LwwBidirectionalInsertsConverge) { bidirectional_inserts_converge(); }

// CORTEX fake_network_tests.cpp, "FakeNetwork: CRDT bidirectional inserts converge". Class (a).
TEST(CortexFakeNetwork, CrdtBidirectionalInsertsConverge) { bidirectional_inserts_converge(); }

// CORTEX fake_network_tests.cpp, "FakeNetwork: LWW insert fans out to all agents in a
// three-node cluster". Class (a).
TEST(CortexFakeNetwork, LwwInsertFansOutToAllAgentsInAThreeNodeCluster) {
  Net net;
  int a = net.add(1), b = net.add(2), c = net.add(3);
  net.pump();
  NodeId id = commit_robot(*net.nodes[a].g, "robot_a");
  net.pump();
  EXPECT_TRUE(net.nodes[b].g->has_node(id));
  EXPECT_TRUE(net.nodes[c].g->has_node(id));
}

// ---------------------------------------------------------------------------------------------
// Delivery controls: drop + recovery. CORTEX recovers with an explicit full-graph sync; Quiver's
// replicators find what is missing from each other's heartbeats and pull it (deltas from the
// relay buffer, or a state transfer), so recovery is time passing on the network.

// CORTEX fake_network_tests.cpp, "FakeNetwork: dropped deltas are recovered by full-graph sync".
// Class (a).
TEST(CortexFakeNetwork, DroppedDeltasAreRecoveredByFullGraphSync) {
  Net net;
  int a = net.add(1), b = net.add(2);
  net.pump();
  net.drop = [](const agents::Packet& p) { return p.sample.topic == agents::DdsTopic::kDelta; };
  NodeId n1 = commit_robot(*net.nodes[a].g, "robot_a");
  NodeId n2 = commit_robot(*net.nodes[a].g, "robot_b");
  net.pump();
  EXPECT_TRUE(net.inflight.empty());
  EXPECT_FALSE(net.nodes[b].g->has_node(n1));
  EXPECT_FALSE(net.nodes[b].g->has_node(n2));
  net.drop = nullptr;
  net.advance(kSecond);
  EXPECT_TRUE(net.nodes[b].g->has_node(n1));
  EXPECT_TRUE(net.nodes[b].g->has_node(n2));
  EXPECT_EQ(net.nodes[a].g->node_count(), net.nodes[b].g->node_count());
}

// CORTEX fake_network_tests.cpp, "FakeNetwork: partial drop then full-graph sync". Class (a): the
// deltas after the lost ones apply at once (they do not wait for the gap), and the gap is
// recovered.
TEST(CortexFakeNetwork, PartialDropThenFullGraphSync) {
  Net net;
  int a = net.add(1), b = net.add(2);
  net.pump();
  int to_drop = 2;
  net.drop = [&](const agents::Packet& p) {
    return p.sample.topic == agents::DdsTopic::kDelta && to_drop-- > 0;
  };
  std::vector<NodeId> ids;
  for (int i = 0; i < 4; ++i) ids.push_back(commit_robot(*net.nodes[a].g, "r" + std::to_string(1000 + i)));
  net.pump();
  Graph& gb = *net.nodes[b].g;
  EXPECT_FALSE(gb.has_node(ids[0]));
  EXPECT_FALSE(gb.has_node(ids[1]));
  EXPECT_TRUE(gb.has_node(ids[2]));
  EXPECT_TRUE(gb.has_node(ids[3]));
  net.drop = nullptr;
  net.advance(kSecond);
  EXPECT_EQ(net.nodes[a].g->node_count(), gb.node_count());
  for (NodeId id : ids) EXPECT_TRUE(gb.has_node(id));
}

// ---------------------------------------------------------------------------------------------
// Partition / rejoin

// CORTEX fake_network_tests.cpp, "FakeNetwork: partitioned agent catches up via buffered
// messages". Class (a): CORTEX flushes a buffer on rejoin; here nothing reaches B while it is cut
// off, and after the partition heals it pulls what it missed.
TEST(CortexFakeNetwork, PartitionedAgentCatchesUpViaBufferedMessages) {
  Net net;
  int a = net.add(1), b = net.add(2);
  net.pump();
  NodeId first = commit_robot(*net.nodes[a].g, "robot_a");
  net.pump();
  ASSERT_TRUE(net.nodes[b].g->has_node(first));
  bool partitioned = true;
  net.drop = [&](const agents::Packet& p) { return partitioned && (p.from == b || p.to == b); };
  std::vector<NodeId> ids;
  for (int i = 0; i < 3; ++i) ids.push_back(commit_robot(*net.nodes[a].g, "r" + std::to_string(2000 + i)));
  net.advance(kSecond / 2);
  for (NodeId id : ids) EXPECT_FALSE(net.nodes[b].g->has_node(id));
  partitioned = false;
  net.advance(2 * kSecond);
  for (NodeId id : ids) EXPECT_TRUE(net.nodes[b].g->has_node(id));
  EXPECT_EQ(net.nodes[a].g->node_count(), net.nodes[b].g->node_count());
}

// CORTEX fake_network_tests.cpp, "FakeNetwork: cold-start agent synced via full-graph import".
// Class (a): A has 5 nodes that B never received (B starts afterwards); B ends with all 5.
TEST(CortexFakeNetwork, ColdStartAgentSyncedViaFullGraphImport) {
  Net net;
  int a = net.add(1);
  for (int i = 0; i < 5; ++i) commit_robot(*net.nodes[a].g, "r" + std::to_string(1000 + i));
  int b = net.add(2);
  EXPECT_EQ(net.nodes[a].g->node_count(), 5u);
  EXPECT_EQ(net.nodes[b].g->node_count(), 0u);
  net.advance(kSecond);
  EXPECT_EQ(net.nodes[b].g->node_count(), 5u);
  EXPECT_EQ(net.nodes[a].g->digest(), net.nodes[b].g->digest());
}

// ---------------------------------------------------------------------------------------------
// Edge synchronisation

// CORTEX fake_network_tests.cpp, "FakeNetwork: LWW edge insert propagates". Class (a), for an RT
// edge (with a pose) and a symbolic one.
TEST(CortexFakeNetwork, LwwEdgeInsertPropagates) {
  Net net;
  int a = net.add(1), b = net.add(2);
  net.pump();
  Graph& ga = *net.nodes[a].g;
  NodeId n10 = commit_robot(ga, "r10"), n11 = commit_robot(ga, "r11");
  net.pump();
  {
    auto tx = ga.begin();
    ASSERT_TRUE(tx.set_rt(n10, n11, Pose::identity(), 1).ok());
    ASSERT_TRUE(tx.insert_edge(n10, n11, kLink).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  net.pump();
  EXPECT_TRUE(net.nodes[b].g->has_edge(n10, n11, "RT"));
  EXPECT_TRUE(net.nodes[b].g->has_edge(n10, n11, kLink));
}

// CORTEX fake_network_tests.cpp, "FakeNetwork: LWW edge delete propagates". Class (a).
TEST(CortexFakeNetwork, LwwEdgeDeletePropagates) {
  Net net;
  int a = net.add(1), b = net.add(2);
  net.pump();
  Graph& ga = *net.nodes[a].g;
  NodeId n10 = commit_robot(ga, "r10"), n11 = commit_robot(ga, "r11");
  {
    auto tx = ga.begin();
    ASSERT_TRUE(tx.set_rt(n10, n11, Pose::identity(), 1).ok());
    ASSERT_TRUE(tx.insert_edge(n10, n11, kLink).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  net.pump();
  ASSERT_TRUE(net.nodes[b].g->has_edge(n10, n11, "RT"));
  ASSERT_TRUE(net.nodes[b].g->has_edge(n10, n11, kLink));
  {
    auto tx = ga.begin();
    ASSERT_TRUE(tx.delete_edge(n10, n11, "RT").ok());
    ASSERT_TRUE(tx.delete_edge(n10, n11, kLink).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  net.pump();
  EXPECT_FALSE(net.nodes[b].g->has_edge(n10, n11, "RT"));
  EXPECT_FALSE(net.nodes[b].g->has_edge(n10, n11, kLink));
}

}  // namespace
}  // namespace quiver::cortex_tests
