// Translation of RoboComp CORTEX tests/synchronization/graph_synchronization.cpp onto Quiver.
// CORTEX runs two DSRGraph agents over DDS and waits on the wall clock; here two replicas with
// their Replicators talk over the in-memory test network (tests/common/test_net.h) on
// simulated time. CORTEX's config files are DSR JSON worlds; they are read with
// interop::import_dsr() (the worlds below are small ones written for these tests).

#include <gtest/gtest.h>

#include <string>

#include "quiver/graph/graph.h"
#include "quiver/interop/dsr.h"
#include "test_net.h"

namespace quiver::cortex_tests {
namespace {

using agents::Net;
using graph::Graph;
using graph::NodeId;
using graph::ReplicaId;
using graph::Value;

// A world with only a root (CORTEX's "empty" config file: one root node with a level).
constexpr const char* kRootOnlyWorld = R"({"DSRModel": {"symbols": {
  "7": {"id": "7", "name": "root", "type": "root", "links": [],
        "attribute": {"level": {"type": 1, "value": 0}}}}}})";

// A world with RT edges: root -> room -> robot (CORTEX's "edge" config file has this shape).
constexpr const char* kEdgeWorld = R"({"DSRModel": {"symbols": {
  "7": {"id": "7", "name": "root", "type": "root",
        "attribute": {"level": {"type": 1, "value": 0}, "color": {"type": 0, "value": "green"}},
        "links": [{"src": "7", "dst": "8", "label": "RT",
                   "linkAttribute": {"rt_translation": {"type": 3, "value": [0, 0, 0]},
                                     "rt_rotation_euler_xyz": {"type": 3, "value": [0, 0, 0]}}}]},
  "8": {"id": "8", "name": "room", "type": "room",
        "attribute": {"level": {"type": 1, "value": 1}, "width": {"type": 1, "value": 5000}},
        "links": [{"src": "8", "dst": "9", "label": "RT",
                   "linkAttribute": {"rt_translation": {"type": 3, "value": [100, 0, 0]},
                                     "rt_rotation_euler_xyz": {"type": 3, "value": [0, 0, 0]}}}]},
  "9": {"id": "9", "name": "robot", "type": "omnirobot",
        "attribute": {"level": {"type": 1, "value": 2}, "port": {"type": 1, "value": 12238}},
        "links": []}}}})";

constexpr std::int64_t kSecond = 1'000'000'000;

void load(Graph& g, const char* world) {
  auto r = interop::import_dsr(g, world, "world.json");
  ASSERT_TRUE(r.ok()) << r.error().to_string();
}

// CORTEX graph_synchronization.cpp, "Connect and receive the graph from other agent" (GENERATE
// over the edge config and the empty config). Class (a): an agent joining later receives the
// whole graph of the agent that loaded the file.
TEST(CortexGraphSynchronization, ConnectAndReceiveTheGraphFromOtherAgent) {
  for (const char* world : {kEdgeWorld, kRootOnlyWorld}) {
    SCOPED_TRACE(world == kEdgeWorld ? "edge config" : "empty config");
    Net net;
    int loader = net.add(101);
    load(*net.nodes[loader].g, world);
    ASSERT_GT(net.nodes[loader].g->node_count(), 0u);
    int joiner = net.add(102);
    EXPECT_EQ(net.nodes[joiner].g->node_count(), 0u);
    net.advance(kSecond / 5);  // CORTEX sleeps 200 ms
    const Graph& a = *net.nodes[loader].g;
    const Graph& b = *net.nodes[joiner].g;
    EXPECT_EQ(b.node_count(), a.node_count());
    EXPECT_EQ(b.edge_count(), a.edge_count());
    EXPECT_EQ(b.digest(), a.digest());
  }
}

// CORTEX graph_synchronization.cpp, "Same-process agents discover each other and exchange
// updates" (GENERATE same_host true/false). Class (a): both agents see each other, and an
// attribute each one adds to "root" reaches the other. CORTEX's same_host flag chooses a DDS
// transport (shared memory or UDP); the in-memory network has no such choice, so the case runs
// once.
TEST(CortexGraphSynchronization, SameProcessAgentsDiscoverEachOtherAndExchangeUpdates) {
  Net net;
  int loader = net.add(201);
  load(*net.nodes[loader].g, kEdgeWorld);
  int follower = net.add(202);
  net.advance(kSecond / 2);
  Graph& gl = *net.nodes[loader].g;
  Graph& gf = *net.nodes[follower].g;
  ASSERT_EQ(gf.node_count(), gl.node_count());
  auto alive_peers = [&](int i) {
    int n = 0;
    for (const auto& p : net.nodes[i].rep->peers())
      if (p.alive) ++n;
    return n;
  };
  EXPECT_GT(alive_peers(loader), 0);
  EXPECT_GT(alive_peers(follower), 0);

  auto root_l = gl.find_node("root");
  ASSERT_TRUE(root_l.has_value());
  {
    auto tx = gl.begin();
    ASSERT_TRUE(tx.set(*root_l, "same_process_loader", Value("loader")).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  net.pump();
  auto root_f = gf.find_node("root");
  ASSERT_TRUE(root_f.has_value());
  EXPECT_EQ(gf.get<std::string>(*root_f, "same_process_loader").value_or(""), "loader");
  {
    auto tx = gf.begin();
    ASSERT_TRUE(tx.set(*root_f, "same_process_follower", Value("follower")).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  net.pump();
  EXPECT_EQ(gl.get<std::string>(*root_l, "same_process_follower").value_or(""), "follower");
}

// CORTEX graph_synchronization.cpp, "Full graph join does not leave empty node registers after
// local deletion". Class (a): a full state taken while the node existed, joined after the node
// was deleted, does not bring it back, and the node count is what it was before the insert.
TEST(CortexGraphSynchronization, FullGraphJoinDoesNotLeaveEmptyNodeRegistersAfterLocalDeletion) {
  Graph g(ReplicaId{301, 1});
  load(g, kRootOnlyWorld);
  const std::size_t initial = g.node_count();
  NodeId id;
  {
    auto tx = g.begin();
    id = tx.create_node("testtype", "regression_node").value();
    ASSERT_TRUE(tx.commit().ok());
  }
  ASSERT_EQ(g.node_count(), initial + 1);
  graph::GraphDelta full = g.state();  // the full graph, as CORTEX copies its map
  {
    auto tx = g.begin();
    ASSERT_TRUE(tx.delete_node(id).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  ASSERT_EQ(g.node_count(), initial);
  ASSERT_FALSE(g.has_node(id));
  g.merge(full);
  EXPECT_EQ(g.node_count(), initial);
  EXPECT_FALSE(g.has_node(id));
  EXPECT_FALSE(g.find_node("regression_node").has_value());
  EXPECT_TRUE(g.check_invariants().empty());
}

}  // namespace
}  // namespace quiver::cortex_tests
