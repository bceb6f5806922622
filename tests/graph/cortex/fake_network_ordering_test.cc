// Translation of RoboComp CORTEX tests/synchronization/fake_network_tests.cpp onto Quiver, its
// cases about the order in which deltas reach an engine: attribute update ordering, delete vs.
// insert conflicts, out-of-order delivery, attribute updates targeting deleted entities, pending
// items and deletes (tombstones), and the CRDT backend's out-of-order twins. They record every
// delta a Graph commits and join them into another Graph in the order the case wants
// (Graph::merge is the engine's apply_remote_*). Shared helpers and the mapping notes are in
// fake_network_fixture.h.

#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>
#include <vector>

#include "fake_network_fixture.h"

namespace quiver::cortex_tests {
namespace {

using graph::EdgeKey;

// A Recorder (cortex_graph_fixture.h) is a replica whose committed deltas are kept, to be delivered
// by hand in any order.

// ---------------------------------------------------------------------------------------------
// Attribute update ordering. CORTEX stamps each write with a wall-clock timestamp chosen by the
// test and the highest timestamp wins. Quiver orders writes by causality: a write supersedes
// every value its replica had seen, whatever order the deltas arrive in; writes that saw
// nothing of each other are concurrent, all kept (attr_values) with one deterministic winner.

// CORTEX fake_network_tests.cpp, "FakeNetwork: LWW stale attr update (older ts) is rejected".
// Class (b): "older" is causally older here (a write the newer one superseded), not an older
// timestamp. The newer write arrives first, the stale one after: the stale one does not overwrite.
// Concurrent writes are not ordered by timestamp: both are kept and the same one wins everywhere.
TEST(CortexFakeNetwork, LwwStaleAttrUpdateOlderTsIsRejected) {
  Recorder a(1), writer(3);
  Graph b(ReplicaId{2, 1});
  NodeId id;
  GraphDelta ins = a.write([&](Transaction& tx) { id = robot(tx, "robot_a"); });
  b.merge(ins);
  writer.g.merge(ins);
  GraphDelta stale = writer.write([&](Transaction& tx) { ASSERT_TRUE(tx.set(id, "level", Value::int32(3)).ok()); });
  GraphDelta newer = writer.write([&](Transaction& tx) { ASSERT_TRUE(tx.set(id, "level", Value::int32(9)).ok()); });
  b.merge(newer);
  b.merge(stale);
  EXPECT_EQ(level(b, id), 9);
  EXPECT_EQ(b.attr_values(id, Symbol("level")).size(), 1u) << "the stale value is superseded, not a conflict";

  // Concurrent writes (neither saw the other): no timestamp decides; both values are kept and
  // both replicas pick the same winner.
  GraphDelta from_a = a.write([&](Transaction& tx) { ASSERT_TRUE(tx.set(id, "level", Value::int32(5)).ok()); });
  a.g.merge(newer);
  a.g.merge(stale);
  b.merge(from_a);
  EXPECT_EQ(a.g.attr_values(id, Symbol("level")).size(), 2u);
  EXPECT_EQ(level(a.g, id), level(b, id));
  EXPECT_EQ(a.g.digest(), b.digest());
}

void settles_on_latest(bool reverse) {
  Recorder a(1), writer(3);
  Graph b(ReplicaId{2, 1});
  NodeId id;
  GraphDelta ins = a.write([&](Transaction& tx) { id = robot(tx, "robot_a"); });
  b.merge(ins);
  writer.g.merge(ins);
  GraphDelta first = writer.write([&](Transaction& tx) { ASSERT_TRUE(tx.set(id, "level", Value::int32(42)).ok()); });
  GraphDelta second = writer.write([&](Transaction& tx) { ASSERT_TRUE(tx.set(id, "level", Value::int32(99)).ok()); });
  for (Graph* g : {&a.g, &b}) {
    if (reverse) {
      g->merge(second);
      g->merge(first);
    } else {
      g->merge(first);
      g->merge(second);
    }
  }
  EXPECT_EQ(level(a.g, id), 99);
  EXPECT_EQ(level(b, id), 99);
  EXPECT_EQ(a.g.attr_values(id, Symbol("level")).size(), 1u);
}

// CORTEX fake_network_tests.cpp, "FakeNetwork: LWW out-of-order attr delivery settles on highest
// timestamp". Class (b): the later write of a causal chain wins (no timestamps); delivered in
// order to both replicas, both settle on it.
TEST(CortexFakeNetwork, LwwOutOfOrderAttrDeliverySettlesOnHighestTimestamp) { settles_on_latest(false); }

// CORTEX fake_network_tests.cpp, "FakeNetwork: LWW reverse attr delivery still converges to
// highest timestamp". Class (b): as above, with the later write delivered first.
TEST(CortexFakeNetwork, LwwReverseAttrDeliveryStillConvergesToHighestTimestamp) { settles_on_latest(true); }

// ---------------------------------------------------------------------------------------------
// Delete vs. insert conflicts

// CORTEX fake_network_tests.cpp, "FakeNetwork: LWW delete (newer ts) suppresses concurrent stale
// insert". Class (b): CORTEX lets a third agent re-send an insert of the same id with an older
// timestamp. Ids are creation dots in Quiver and cannot be re-inserted under another author; the
// closest stale inserts are the node's own creation delta arriving again after the delete, and a
// write of a third replica made concurrently with the delete: neither brings the node back.
TEST(CortexFakeNetwork, LwwDeleteNewerTsSuppressesConcurrentStaleInsert) {
  Recorder a(1), third(3);
  Graph b(ReplicaId{2, 1});
  NodeId id;
  GraphDelta ins = a.write([&](Transaction& tx) { id = robot(tx, "robot_a"); });
  b.merge(ins);
  third.g.merge(ins);
  GraphDelta del = a.write([&](Transaction& tx) { ASSERT_TRUE(tx.delete_node(id).ok()); });
  GraphDelta concurrent = third.write([&](Transaction& tx) { ASSERT_TRUE(tx.set(id, "name_hint", Value("ghost")).ok()); });
  b.merge(del);
  for (Graph* g : {&a.g, &b}) {
    g->merge(ins);  // the stale insert again
    g->merge(concurrent);
  }
  EXPECT_FALSE(a.g.has_node(id));
  EXPECT_FALSE(b.has_node(id));
  EXPECT_FALSE(b.find_node("robot_a").has_value());
  EXPECT_EQ(a.g.digest(), b.digest());
}

// CORTEX fake_network_tests.cpp, "FakeNetwork: LWW newer remote insert (higher ts) overrides prior
// delete". Class (b): in CORTEX a later insert of the same id revives it under the name
// "phoenix". A deleted Quiver id never comes back; a later insert is a new node with a new id.
// Both replicas end with "phoenix" (new id) and without the deleted id.
TEST(CortexFakeNetwork, LwwNewerRemoteInsertHigherTsOverridesPriorDelete) {
  Recorder a(1), third(3);
  Graph b(ReplicaId{2, 1});
  NodeId id;
  GraphDelta ins = a.write([&](Transaction& tx) { id = robot(tx, "robot_a"); });
  b.merge(ins);
  third.g.merge(ins);
  GraphDelta del = a.write([&](Transaction& tx) { ASSERT_TRUE(tx.delete_node(id).ok()); });
  third.g.merge(del);  // the newer insert comes after the delete
  NodeId phoenix;
  GraphDelta again = third.write([&](Transaction& tx) { phoenix = robot(tx, "phoenix"); });
  b.merge(del);
  a.g.merge(again);
  b.merge(again);
  for (const Graph* g : {&a.g, &b}) {
    EXPECT_FALSE(g->has_node(id));
    ASSERT_TRUE(g->has_node(phoenix));
    EXPECT_NE(phoenix, id);
    EXPECT_EQ(g->name_of(phoenix), "phoenix");
  }
}

// ---------------------------------------------------------------------------------------------
// Out-of-order delivery. CORTEX's engines buffer a delta whose parent is missing and apply it when
// the parent arrives. Quiver joins every delta at once (joins commute); an edge is visible only
// while both endpoints are, and an attribute only while its node (or edge) is.

struct EdgeScenario {
  Recorder a{1};
  NodeId n10, n11;
  GraphDelta d_from, d_to, d_edge;
  EdgeScenario() {
    d_from = a.write([&](Transaction& tx) { n10 = robot(tx, "r_from"); });
    d_to = a.write([&](Transaction& tx) { n11 = robot(tx, "r_to"); });
    d_edge = a.write([&](Transaction& tx) { ASSERT_TRUE(tx.insert_edge(n10, n11, kLink).ok()); });
  }
};

void edge_before_to_node() {
  EdgeScenario s;
  Graph b(ReplicaId{2, 1});
  b.merge(s.d_from);
  ASSERT_TRUE(b.has_node(s.n10));
  b.merge(s.d_edge);
  EXPECT_FALSE(b.has_edge(s.n10, s.n11, kLink));
  b.merge(s.d_to);
  EXPECT_TRUE(b.has_node(s.n11));
  EXPECT_TRUE(b.has_edge(s.n10, s.n11, kLink));
  EXPECT_EQ(b.digest(), s.a.g.digest());
}

void edge_before_from_node() {
  EdgeScenario s;
  Graph b(ReplicaId{2, 1});
  b.merge(s.d_to);
  ASSERT_TRUE(b.has_node(s.n11));
  ASSERT_FALSE(b.has_node(s.n10));
  b.merge(s.d_edge);
  EXPECT_FALSE(b.has_edge(s.n10, s.n11, kLink));
  b.merge(s.d_from);
  EXPECT_TRUE(b.has_node(s.n10));
  EXPECT_TRUE(b.has_edge(s.n10, s.n11, kLink));
  EXPECT_EQ(b.digest(), s.a.g.digest());
}

void node_attr_before_node() {
  Recorder a(1);
  NodeId id;
  GraphDelta ins = a.write([&](Transaction& tx) { id = robot(tx, "robot_a"); });
  GraphDelta upd = a.write([&](Transaction& tx) { ASSERT_TRUE(tx.set(id, "level", Value::int32(99)).ok()); });
  Graph b(ReplicaId{2, 1});
  b.merge(upd);
  EXPECT_FALSE(b.has_node(id));
  b.merge(ins);
  ASSERT_TRUE(b.has_node(id));
  EXPECT_EQ(level(b, id), 99);
}

void edge_attr_before_edge() {
  Recorder a(1);
  NodeId n10, n11;
  GraphDelta nodes = a.write([&](Transaction& tx) {
    n10 = robot(tx, "r10");
    n11 = robot(tx, "r11");
  });
  Graph b(ReplicaId{2, 1});
  b.merge(nodes);
  GraphDelta edge = a.write([&](Transaction& tx) { ASSERT_TRUE(tx.insert_edge(n10, n11, kLink).ok()); });
  GraphDelta upd = a.write([&](Transaction& tx) {
    ASSERT_TRUE(tx.set_edge_attr(EdgeKey{n10, n11, Symbol(kLink)}, "weight", Value::int32(99)).ok());
  });
  b.merge(upd);
  EXPECT_FALSE(b.has_edge(n10, n11, kLink));
  b.merge(edge);
  ASSERT_TRUE(b.has_edge(n10, n11, kLink));
  EXPECT_EQ(b.get<std::int32_t>(EdgeKey{n10, n11, Symbol(kLink)}, "weight").value_or(-1), 99);
}

void chained_edge_attr_edge_nodes() {
  Recorder a(1);
  NodeId n10, n11;
  GraphDelta d10 = a.write([&](Transaction& tx) { n10 = robot(tx, "r_from"); });
  GraphDelta d11 = a.write([&](Transaction& tx) { n11 = robot(tx, "r_to"); });
  GraphDelta edge = a.write([&](Transaction& tx) { ASSERT_TRUE(tx.insert_edge(n10, n11, kLink).ok()); });
  GraphDelta attr = a.write([&](Transaction& tx) {
    ASSERT_TRUE(tx.set_edge_attr(EdgeKey{n10, n11, Symbol(kLink)}, "weight", Value::int32(42)).ok());
  });
  Graph b(ReplicaId{2, 1});
  b.merge(attr);
  EXPECT_FALSE(b.has_edge(n10, n11, kLink));
  b.merge(edge);
  EXPECT_FALSE(b.has_edge(n10, n11, kLink));
  b.merge(d10);
  EXPECT_TRUE(b.has_node(n10));
  EXPECT_FALSE(b.has_edge(n10, n11, kLink));
  b.merge(d11);
  EXPECT_TRUE(b.has_node(n11));
  ASSERT_TRUE(b.has_edge(n10, n11, kLink));
  EXPECT_EQ(b.get<std::int32_t>(EdgeKey{n10, n11, Symbol(kLink)}, "weight").value_or(-1), 42);
  EXPECT_EQ(b.digest(), a.g.digest());
}

// CORTEX fake_network_tests.cpp, "FakeNetwork: LWW edge delta arrives before 'to' node: buffered
// and applied". Class (a).
TEST(CortexFakeNetwork, LwwEdgeDeltaArrivesBeforeToNodeBufferedAndApplied) { edge_before_to_node(); }

// CORTEX fake_network_tests.cpp, "FakeNetwork: LWW edge delta arrives before 'from' node:
// buffered and applied". Class (a).
TEST(CortexFakeNetwork, LwwEdgeDeltaArrivesBeforeFromNodeBufferedAndApplied) { edge_before_from_node(); }

// CORTEX fake_network_tests.cpp, "FakeNetwork: LWW node attr batch arrives before node creation:
// buffered and applied". Class (a).
TEST(CortexFakeNetwork, LwwNodeAttrBatchArrivesBeforeNodeCreationBufferedAndApplied) { node_attr_before_node(); }

// CORTEX fake_network_tests.cpp, "FakeNetwork: LWW edge attr batch arrives before edge creation:
// buffered and applied". Class (a).
TEST(CortexFakeNetwork, LwwEdgeAttrBatchArrivesBeforeEdgeCreationBufferedAndApplied) { edge_attr_before_edge(); }

// ---------------------------------------------------------------------------------------------
// Attribute updates targeting deleted entities

// CORTEX fake_network_tests.cpp, "FakeNetwork: LWW node attr batch for deleted node is silently
// ignored". Class (a): a write made by a third replica that had not seen the delete, arriving
// after it, does not resurrect the node.
TEST(CortexFakeNetwork, LwwNodeAttrBatchForDeletedNodeIsSilentlyIgnored) {
  Recorder a(1), third(3);
  Graph b(ReplicaId{2, 1});
  NodeId id;
  GraphDelta ins = a.write([&](Transaction& tx) { id = robot(tx, "robot_a"); });
  b.merge(ins);
  third.g.merge(ins);
  ASSERT_TRUE(b.has_node(id));
  GraphDelta del = a.write([&](Transaction& tx) { ASSERT_TRUE(tx.delete_node(id).ok()); });
  b.merge(del);
  ASSERT_FALSE(b.has_node(id));
  GraphDelta late = third.write([&](Transaction& tx) { ASSERT_TRUE(tx.set(id, "level", Value::int32(99)).ok()); });
  b.merge(late);
  EXPECT_FALSE(b.has_node(id));
  EXPECT_EQ(b.node_count(), 0u);
}

// CORTEX fake_network_tests.cpp, "FakeNetwork: LWW edge attr batch for deleted edge is silently
// ignored". Class (a): an attribute write of a third replica that had not seen the edge's delete,
// arriving after it, does not recreate the edge.
TEST(CortexFakeNetwork, LwwEdgeAttrBatchForDeletedEdgeIsSilentlyIgnored) {
  Recorder a(1), third(3);
  Graph b(ReplicaId{2, 1});
  NodeId n10, n11;
  GraphDelta setup = a.write([&](Transaction& tx) {
    n10 = robot(tx, "r10");
    n11 = robot(tx, "r11");
    ASSERT_TRUE(tx.insert_edge(n10, n11, kLink).ok());
  });
  b.merge(setup);
  third.g.merge(setup);
  ASSERT_TRUE(b.has_edge(n10, n11, kLink));
  GraphDelta del = a.write([&](Transaction& tx) { ASSERT_TRUE(tx.delete_edge(n10, n11, kLink).ok()); });
  b.merge(del);
  ASSERT_FALSE(b.has_edge(n10, n11, kLink));
  GraphDelta late = third.write([&](Transaction& tx) {
    ASSERT_TRUE(tx.set_edge_attr(EdgeKey{n10, n11, Symbol(kLink)}, "weight", Value::int32(99)).ok());
  });
  b.merge(late);
  EXPECT_FALSE(b.has_edge(n10, n11, kLink));
}

// ---------------------------------------------------------------------------------------------
// Pending items and deletes (CORTEX's tombstone scenarios). The writer's causal order stands in
// for CORTEX's timestamps: the deltas reach a fresh replica in the order the case lists.

// CORTEX fake_network_tests.cpp, "FakeNetwork: LWW pending node attr discarded when node
// tombstoned before creation". Class (a): attribute write, then delete, then the (older)
// creation arrive; the node never appears.
TEST(CortexFakeNetwork, LwwPendingNodeAttrDiscardedWhenNodeTombstonedBeforeCreation) {
  Recorder a(2);
  NodeId id;
  GraphDelta ins = a.write([&](Transaction& tx) { id = robot(tx, "robot_a"); });
  GraphDelta attr = a.write([&](Transaction& tx) { ASSERT_TRUE(tx.set(id, "level", Value::int32(99)).ok()); });
  GraphDelta del = a.write([&](Transaction& tx) { ASSERT_TRUE(tx.delete_node(id).ok()); });
  Graph b(ReplicaId{1, 1});
  b.merge(attr);
  EXPECT_FALSE(b.has_node(id));
  b.merge(del);
  EXPECT_FALSE(b.has_node(id));
  b.merge(ins);
  EXPECT_FALSE(b.has_node(id));
  EXPECT_EQ(b.node_count(), 0u);
}

// CORTEX fake_network_tests.cpp, "FakeNetwork: LWW pending edge attr discarded when edge
// tombstoned before creation". Class (a).
TEST(CortexFakeNetwork, LwwPendingEdgeAttrDiscardedWhenEdgeTombstonedBeforeCreation) {
  Recorder a(2);
  NodeId n10, n11;
  GraphDelta nodes = a.write([&](Transaction& tx) {
    n10 = robot(tx, "r_from");
    n11 = robot(tx, "r_to");
  });
  const EdgeKey key{n10, n11, Symbol(kLink)};
  GraphDelta ins = a.write([&](Transaction& tx) { ASSERT_TRUE(tx.insert_edge(n10, n11, kLink).ok()); });
  GraphDelta attr = a.write([&](Transaction& tx) { ASSERT_TRUE(tx.set_edge_attr(key, "weight", Value::int32(99)).ok()); });
  GraphDelta del = a.write([&](Transaction& tx) { ASSERT_TRUE(tx.delete_edge(n10, n11, kLink).ok()); });
  Graph b(ReplicaId{1, 1});
  b.merge(nodes);
  b.merge(attr);
  EXPECT_FALSE(b.has_edge(n10, n11, kLink));
  b.merge(del);
  EXPECT_FALSE(b.has_edge(n10, n11, kLink));
  b.merge(ins);
  EXPECT_FALSE(b.has_edge(n10, n11, kLink));
  EXPECT_TRUE(b.edges_from(n10).empty());
}

// CORTEX fake_network_tests.cpp, "FakeNetwork: LWW newer edge attr survives older delete
// tombstone". Class (a): the writer deletes the edge, inserts it again and then sets its weight;
// the weight arrives first, then the delete, then the re-insert: the edge is there with weight 99
// (and the original insert arriving last changes nothing).
TEST(CortexFakeNetwork, LwwNewerEdgeAttrSurvivesOlderDeleteTombstone) {
  Recorder a(2);
  NodeId n10, n11;
  GraphDelta nodes = a.write([&](Transaction& tx) {
    n10 = robot(tx, "r_from");
    n11 = robot(tx, "r_to");
  });
  const EdgeKey key{n10, n11, Symbol(kLink)};
  GraphDelta first = a.write([&](Transaction& tx) { ASSERT_TRUE(tx.insert_edge(n10, n11, kLink).ok()); });
  GraphDelta del = a.write([&](Transaction& tx) { ASSERT_TRUE(tx.delete_edge(n10, n11, kLink).ok()); });
  GraphDelta again = a.write([&](Transaction& tx) { ASSERT_TRUE(tx.insert_edge(n10, n11, kLink).ok()); });
  GraphDelta attr = a.write([&](Transaction& tx) { ASSERT_TRUE(tx.set_edge_attr(key, "weight", Value::int32(99)).ok()); });
  Graph b(ReplicaId{1, 1});
  b.merge(nodes);
  b.merge(attr);
  EXPECT_FALSE(b.has_edge(n10, n11, kLink));
  b.merge(del);
  EXPECT_FALSE(b.has_edge(n10, n11, kLink));
  b.merge(again);
  ASSERT_TRUE(b.has_edge(n10, n11, kLink));
  EXPECT_EQ(b.get<std::int32_t>(key, "weight").value_or(-1), 99);
  b.merge(first);
  ASSERT_TRUE(b.has_edge(n10, n11, kLink));
  EXPECT_EQ(b.get<std::int32_t>(key, "weight").value_or(-1), 99);
  EXPECT_EQ(b.digest(), a.g.digest());
}

// CORTEX fake_network_tests.cpp, "FakeNetwork: LWW chained out-of-order edge attr then edge then
// nodes". Class (a).
TEST(CortexFakeNetwork, LwwChainedOutOfOrderEdgeAttrThenEdgeThenNodes) { chained_edge_attr_edge_nodes(); }

// ---------------------------------------------------------------------------------------------
// CRDT backend: the same out-of-order scenarios (Quiver has one mode).

// CORTEX fake_network_tests.cpp, "FakeNetwork: CRDT edge delta arrives before 'to' node: buffered
// and applied". Class (a).
TEST(CortexFakeNetwork, CrdtEdgeDeltaArrivesBeforeToNodeBufferedAndApplied) { edge_before_to_node(); }

// CORTEX fake_network_tests.cpp, "FakeNetwork: CRDT edge delta arrives before 'from' node:
// buffered and applied". Class (a).
TEST(CortexFakeNetwork, CrdtEdgeDeltaArrivesBeforeFromNodeBufferedAndApplied) { edge_before_from_node(); }

// CORTEX fake_network_tests.cpp, "FakeNetwork: CRDT node attr batch arrives before node creation:
// buffered and applied". Class (a).
TEST(CortexFakeNetwork, CrdtNodeAttrBatchArrivesBeforeNodeCreationBufferedAndApplied) { node_attr_before_node(); }

// CORTEX fake_network_tests.cpp, "FakeNetwork: CRDT edge attr batch arrives before edge creation:
// buffered and applied". Class (a).
TEST(CortexFakeNetwork, CrdtEdgeAttrBatchArrivesBeforeEdgeCreationBufferedAndApplied) { edge_attr_before_edge(); }

// CORTEX fake_network_tests.cpp, "FakeNetwork: CRDT chained out-of-order edge attr then edge then
// nodes". Class (a).
TEST(CortexFakeNetwork, CrdtChainedOutOfOrderEdgeAttrThenEdgeThenNodes) { chained_edge_attr_edge_nodes(); }

}  // namespace
}  // namespace quiver::cortex_tests
