#include "quiver/graph/graph.h"

#include <gtest/gtest.h>

#include "graph_test_util.h"

namespace quiver::graph {
namespace {

using testing::Peer;

Pose at(double x, double y = 0, double z = 0) {
  Pose p;
  p.translation = {x, y, z};
  return p;
}

TEST(GraphTest, CreateReadTypedAttributes) {
  Peer a(1);
  auto tx = a.g.begin();
  auto robot = tx.create_node("robot", "robot", {{Symbol("battery"), Value(0.5)}});
  ASSERT_TRUE(robot.ok());
  ASSERT_TRUE(tx.set(*robot, "label", Value("r1")).ok());
  ASSERT_TRUE(tx.set(*robot, "pos", Value(Vec3f{1, 2, 3})).ok());
  ASSERT_TRUE(tx.set(*robot, "count", Value::int32(7)).ok());
  ASSERT_TRUE(tx.set(*robot, "pose", Value(Mat4d::identity())).ok());
  ASSERT_TRUE(tx.commit().ok());
  EXPECT_EQ(a.g.node_count(), 1u);
  EXPECT_EQ(a.g.name_of(*robot), "robot");
  EXPECT_EQ(a.g.type_of(*robot).str(), "robot");
  EXPECT_EQ(a.g.find_node("robot"), *robot);
  EXPECT_EQ(a.g.get<double>(*robot, "battery").value(), 0.5);
  EXPECT_EQ(a.g.get<std::string>(*robot, "label").value(), "r1");
  EXPECT_EQ((a.g.get<Vec3f>(*robot, "pos").value()), (Vec3f{1, 2, 3}));
  EXPECT_EQ(a.g.get<std::int32_t>(*robot, "count").value(), 7);
  EXPECT_EQ(a.g.get<Mat4d>(*robot, "pose").value(), Mat4d::identity());
  auto wrong = a.g.get<double>(*robot, "label");
  ASSERT_FALSE(wrong.ok());
  EXPECT_EQ(wrong.error().code, ErrorCode::kTypeMismatch);
  EXPECT_NE(wrong.error().message.find("label"), std::string::npos);
  auto missing = a.g.get<double>(*robot, "nope");
  EXPECT_EQ(missing.error().code, ErrorCode::kNotFound);
  EXPECT_EQ(a.g.nodes_of_type("robot"), std::vector<NodeId>{*robot});
}

TEST(GraphTest, InvalidChangesAreRefusedAndRecordNothing) {
  Peer a(1);
  NodeId r = a.add("robot", "robot");
  auto tx = a.g.begin();
  EXPECT_EQ(tx.create_node("x", "robot").error().code, ErrorCode::kAlreadyExists);
  EXPECT_EQ(tx.create_node("x", "").error().code, ErrorCode::kInvalidArgument);
  EXPECT_EQ(tx.insert_edge(r, r, Symbol("RT")).error().code, ErrorCode::kInvalidArgument);
  EXPECT_EQ(tx.set(NodeId{Dot{{9, 9}, 9}}, "x", Value(1.0)).error().code, ErrorCode::kNotFound);
  EXPECT_EQ(tx.insert_edge(r, NodeId{Dot{{9, 9}, 9}}, Symbol("in")).error().code, ErrorCode::kNotFound);
  EXPECT_EQ(tx.set_rt(r, r, Pose{}).error().code, ErrorCode::kInvalidArgument);
  EXPECT_TRUE(tx.empty());
  EXPECT_TRUE(tx.commit().ok());
  EXPECT_EQ(a.outbox.size(), 1u) << "an empty transaction publishes nothing";
}

TEST(GraphTest, EdgesOfSeveralTypesBetweenOnePair) {
  Peer a(1);
  NodeId p = a.add("person", "person"), r = a.add("robot", "robot");
  auto tx = a.g.begin();
  ASSERT_TRUE(tx.insert_edge(r, p, Symbol("is_with")).ok());
  ASSERT_TRUE(tx.insert_edge(r, p, Symbol("speaking"), {{Symbol("text"), Value("hi")}}).ok());
  ASSERT_TRUE(tx.commit().ok());
  EXPECT_EQ(a.g.edges_from(r).size(), 2u);
  EXPECT_EQ(a.g.edges_to(p, Symbol("speaking")).size(), 1u);
  EXPECT_EQ(a.g.edge_attr(EdgeKey{r, p, Symbol("speaking")}, Symbol("text"))->as<std::string>().value(), "hi");
  EXPECT_FALSE(a.g.has_edge(p, r, Symbol("is_with"))) << "no implied inverse edges";
}

TEST(GraphTest, DeleteNodeRemovesAttributesAndIncidentEdges) {
  Peer a(1), b(2);
  NodeId p = a.add("person", "person"), r = a.add("robot", "robot");
  {
    auto tx = a.g.begin();
    ASSERT_TRUE(tx.insert_edge(r, p, Symbol("is_with")).ok());
    ASSERT_TRUE(tx.set(p, "age", Value(std::int64_t{80})).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  b.receive_all(a);
  a.outbox.clear();
  {
    auto tx = a.g.begin();
    ASSERT_TRUE(tx.delete_node(p).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  EXPECT_FALSE(a.g.has_node(p));
  EXPECT_TRUE(a.g.edges_from(r).empty());
  b.receive_all(a);
  EXPECT_FALSE(b.g.has_node(p));
  EXPECT_TRUE(b.g.edges_from(r).empty());
  EXPECT_EQ(a.g.digest(), b.g.digest());
  EXPECT_TRUE(a.g.check_invariants().empty());
}

// AGM's and CORTEX's files use symbolic self-loops r->r(label) as unary predicates; they are edges
// like any other (RT excepted: a frame is not its own parent).
TEST(GraphTest, UnaryPredicatesAreSelfLoopEdges) {
  Peer a(1), b(2);
  NodeId r = a.add("robot", "robot");
  {
    auto tx = a.g.begin();
    ASSERT_TRUE(tx.insert_edge(r, r, Symbol("moving"), {{Symbol("since"), Value(std::int64_t{3})}}).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  ASSERT_EQ(a.g.edges_from(r).size(), 1u);
  ASSERT_EQ(a.g.edges_to(r).size(), 1u);
  EXPECT_EQ(a.g.edges_from(r)[0], (EdgeKey{r, r, Symbol("moving")}));
  EXPECT_EQ(a.g.edge_count(), 1u);
  // The loop travels before its node; it shows once both have arrived.
  b.receive(a.outbox[1]);
  EXPECT_EQ(b.g.edge_count(), 0u);
  b.receive(a.outbox[0]);
  EXPECT_TRUE(b.g.has_edge(r, r, Symbol("moving")));
  EXPECT_EQ(a.g.digest(), b.g.digest());
  a.outbox.clear();
  b.outbox.clear();
  // Deleting the predicate, and deleting its node while a peer writes on the loop.
  {
    auto tx = a.g.begin();
    ASSERT_TRUE(tx.delete_edge(r, r, Symbol("moving")).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  EXPECT_FALSE(a.g.has_edge(r, r, Symbol("moving")));
  {
    auto tx = a.g.begin();
    ASSERT_TRUE(tx.insert_edge(r, r, Symbol("moving")).ok());
    ASSERT_TRUE(tx.delete_node(r).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  {
    auto tx = b.g.begin();
    ASSERT_TRUE(tx.set_edge_attr(EdgeKey{r, r, Symbol("moving")}, Symbol("since"), Value(std::int64_t{4})).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  b.receive_all(a);
  a.receive_all(b);
  EXPECT_FALSE(a.g.has_node(r));
  EXPECT_EQ(a.g.edge_count(), 0u);
  EXPECT_EQ(a.g.digest(), b.g.digest());
  EXPECT_TRUE(a.g.check_invariants().empty());
  EXPECT_TRUE(b.g.check_invariants().empty());
}

TEST(GraphTest, ConcurrentAttributeWriteNeverResurrectsADeletedNode) {
  Peer a(1), b(2);
  NodeId p = a.add("person", "person");
  b.receive_all(a);
  a.outbox.clear();
  {
    auto tx = a.g.begin();
    ASSERT_TRUE(tx.delete_node(p).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  {
    auto tx = b.g.begin();
    ASSERT_TRUE(tx.set(p, "age", Value(std::int64_t{81})).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  std::vector<std::uint8_t> from_b = b.outbox.back();
  b.receive_all(a);
  a.receive(from_b);
  EXPECT_FALSE(a.g.has_node(p));
  EXPECT_FALSE(b.g.has_node(p));
  EXPECT_EQ(a.g.digest(), b.g.digest());
  EXPECT_EQ(a.g.stats().entries, 0u) << "the stray write is collected, not kept as a zombie";
  EXPECT_TRUE(a.g.check_invariants().empty());
  EXPECT_TRUE(b.g.check_invariants().empty());
}

TEST(GraphTest, EdgeIsVisibleOnlyWhenBothEndpointsAre) {
  Peer a(1), b(2);
  NodeId r = a.add("robot", "robot");
  NodeId room = a.add("room", "kitchen");
  {
    auto tx = a.g.begin();
    ASSERT_TRUE(tx.insert_edge(r, room, Symbol("in")).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  // Deliver the edge first, then the nodes.
  b.receive(a.outbox[2]);
  EXPECT_EQ(b.g.edge_count(), 0u);
  EXPECT_TRUE(b.g.check_invariants().empty());
  b.receive(a.outbox[0]);
  EXPECT_EQ(b.g.edge_count(), 0u);
  b.receive(a.outbox[1]);
  EXPECT_TRUE(b.g.has_edge(r, room, Symbol("in")));
  EXPECT_EQ(a.g.digest(), b.g.digest());
}

TEST(GraphTest, EdgeAddWinsOverConcurrentDelete) {
  Peer a(1), b(2);
  NodeId r = a.add("robot", "robot"), k = a.add("room", "kitchen");
  {
    auto tx = a.g.begin();
    ASSERT_TRUE(tx.insert_edge(r, k, Symbol("in")).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  b.receive_all(a);
  a.outbox.clear();
  {
    auto tx = a.g.begin();
    ASSERT_TRUE(tx.delete_edge(r, k, Symbol("in")).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  {
    auto tx = b.g.begin();
    ASSERT_TRUE(tx.insert_edge(r, k, Symbol("in")).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  auto from_b = b.outbox.back();
  b.receive_all(a);
  a.receive(from_b);
  EXPECT_TRUE(a.g.has_edge(r, k, Symbol("in")));
  EXPECT_TRUE(b.g.has_edge(r, k, Symbol("in")));
  EXPECT_EQ(a.g.digest(), b.g.digest());
}

TEST(GraphTest, ConcurrentWritesKeepAllValuesWithTheSameWinner) {
  Peer a(1), b(2);
  NodeId r = a.add("robot", "robot");
  b.receive_all(a);
  a.outbox.clear();
  for (Peer* p : {&a, &b}) {
    auto tx = p->g.begin();
    ASSERT_TRUE(tx.set(r, "goal", Value(p == &a ? "kitchen" : "bedroom")).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  auto from_a = a.outbox.back(), from_b = b.outbox.back();
  a.receive(from_b);
  b.receive(from_a);
  auto va = a.g.attr_values(r, Symbol("goal"));
  auto vb = b.g.attr_values(r, Symbol("goal"));
  ASSERT_EQ(va.size(), 2u) << "the conflict is visible";
  ASSERT_EQ(vb.size(), 2u);
  EXPECT_EQ(*a.g.attr(r, "goal"), *b.g.attr(r, "goal"));
  EXPECT_EQ(va[0].value, *a.g.attr(r, "goal")) << "winner first";
  // Writing again resolves it.
  {
    auto tx = a.g.begin();
    ASSERT_TRUE(tx.set(r, "goal", Value("hall")).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  b.receive(a.outbox.back());
  EXPECT_EQ(b.g.attr_values(r, Symbol("goal")).size(), 1u);
}

TEST(GraphTest, AFencedWriteBeatsAConcurrentStaleOneWhateverTheLamportOrder) {
  // A lock holder at epoch 5 (a) and its successor at epoch 6 (b) write the same attribute
  // concurrently; a's write is later in Lamport order, yet b's must win on every replica.
  Peer a(1), b(2);
  NodeId r = a.add("robot", "robot");
  b.receive_all(a);
  a.outbox.clear();
  b.g.set_fence_provider([](NodeId) { return 6; });
  a.g.set_fence_provider([](NodeId) { return 5; });
  {
    auto tx = b.g.begin();
    ASSERT_TRUE(tx.set(r, "say", Value("stop")).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  for (int i = 0; i < 5; ++i) {  // push a's Lamport clock well past b's
    auto tx = a.g.begin();
    ASSERT_TRUE(tx.set(r, "say", Value("go on " + std::to_string(i))).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  auto from_b = b.outbox.back();
  b.receive_all(a);
  a.receive(from_b);
  EXPECT_EQ(a.g.attr(r, "say")->as<std::string>().value(), "stop");
  EXPECT_EQ(b.g.attr(r, "say")->as<std::string>().value(), "stop");
  auto values = a.g.attr_values(r, Symbol("say"));
  ASSERT_EQ(values.size(), 2u);
  EXPECT_EQ(values[0].fence, 6u);
  EXPECT_EQ(a.g.digest(), b.g.digest());
  // An unfenced write that has seen both supersedes them (the lock is gone).
  a.g.set_fence_provider(nullptr);
  auto tx = a.g.begin();
  ASSERT_TRUE(tx.set(r, "say", Value("idle")).ok());
  ASSERT_TRUE(tx.commit().ok());
  b.receive(a.outbox.back());
  EXPECT_EQ(b.g.attr_values(r, Symbol("say")).size(), 1u);
  EXPECT_EQ(b.g.attr(r, "say")->as<std::string>().value(), "idle");
}

TEST(GraphTest, ConcurrentDuplicateNamesResolveDeterministically) {
  Peer a(1), b(2);
  NodeId pa = a.add("person", "person");
  NodeId pb = b.add("person", "person");
  a.receive_all(b);
  b.receive_all(a);
  EXPECT_EQ(a.g.find_node("person"), b.g.find_node("person"));
  EXPECT_EQ(a.g.namesakes("person").size(), 2u);
  NodeId winner = *a.g.find_node("person");
  NodeId loser = winner == pa ? pb : pa;
  EXPECT_EQ(a.g.name_of(winner), "person");
  EXPECT_NE(a.g.name_of(loser), "person");
  EXPECT_EQ(a.g.name_of(loser), b.g.name_of(loser));
  EXPECT_EQ(a.g.find_node(a.g.name_of(loser)), loser);
  // Locally, the name stays taken.
  auto tx = a.g.begin();
  EXPECT_EQ(tx.create_node("person", "person").error().code, ErrorCode::kAlreadyExists);
}

TEST(GraphTest, RtTreeParentsChildrenAndPoseUpdates) {
  Peer a(1);
  NodeId world = a.add("world", "world"), robot = a.add("robot", "robot"), arm = a.add("arm", "arm");
  {
    auto tx = a.g.begin();
    ASSERT_TRUE(tx.set_rt(world, robot, at(1), 10).ok());
    ASSERT_TRUE(tx.set_rt(robot, arm, at(0, 1), 10).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  EXPECT_EQ(a.g.rt_parent(arm), robot);
  EXPECT_EQ(a.g.rt_children(world), std::vector<NodeId>{robot});
  EXPECT_TRUE(a.g.has_edge(world, robot, symbols::rt()));
  EXPECT_EQ(a.g.rt_edge(robot)->pose.translation[0], 1.0);
  {
    auto tx = a.g.begin();
    ASSERT_TRUE(tx.set_rt(world, robot, at(2), 20).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  EXPECT_EQ(a.g.rt_edge(robot)->pose.translation[0], 2.0);
  EXPECT_EQ(a.g.rt_edge(robot)->stamp, 20);
  EXPECT_EQ(a.g.rt_history(robot).size(), 2u) << "the move's pose (t=10) and the update (t=20)";
  auto tx = a.g.begin();
  auto refused = tx.set_rt(arm, world, at(0));
  EXPECT_EQ(refused.error().code, ErrorCode::kRefused) << "a cycle is refused locally";
}

TEST(GraphTest, ConcurrentReparentingNeverMakesACycle) {
  Peer a(1), b(2);
  NodeId world = a.add("world", "world"), x = a.add("thing", "x"), y = a.add("thing", "y");
  {
    auto tx = a.g.begin();
    ASSERT_TRUE(tx.set_rt(world, x, at(1)).ok());
    ASSERT_TRUE(tx.set_rt(world, y, at(2)).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  b.receive_all(a);
  a.outbox.clear();
  {
    auto tx = a.g.begin();
    ASSERT_TRUE(tx.set_rt(y, x, at(3)).ok());  // x under y
    ASSERT_TRUE(tx.commit().ok());
  }
  {
    auto tx = b.g.begin();
    ASSERT_TRUE(tx.set_rt(x, y, at(4)).ok());  // y under x, concurrently
    ASSERT_TRUE(tx.commit().ok());
  }
  auto from_a = a.outbox.back(), from_b = b.outbox.back();
  a.receive(from_b);
  b.receive(from_a);
  EXPECT_TRUE(a.g.check_invariants().empty());
  EXPECT_TRUE(b.g.check_invariants().empty());
  EXPECT_EQ(a.g.rt_parent(x), b.g.rt_parent(x));
  EXPECT_EQ(a.g.rt_parent(y), b.g.rt_parent(y));
  // Exactly one of the two moves took effect; the other node stayed under the world.
  bool x_under_y = a.g.rt_parent(x) == y, y_under_x = a.g.rt_parent(y) == x;
  EXPECT_NE(x_under_y, y_under_x);
  EXPECT_TRUE(a.g.rt_parent(x) == world || a.g.rt_parent(y) == world);
  EXPECT_EQ(a.g.digest(), b.g.digest());
}

// A move whose new parent is gone falls back to the parent the child had, with the epoch it had
// there but the pose it had when the move was made: a pose change the merge must announce even
// though parent and epoch stay the same.
TEST(GraphTest, AMoveThatFallsBackAnnouncesThePoseItBrings) {
  Peer a(1), b(2);
  NodeId p = a.add("table", "p"), q = a.add("shelf", "q"), c = a.add("mug", "c");
  {
    auto tx = a.g.begin();
    ASSERT_TRUE(tx.set_rt(p, c, at(1), 10).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  b.receive_all(a);
  {
    auto tx = a.g.begin();
    ASSERT_TRUE(tx.set_rt(p, c, at(2), 20).ok());  // a pose update b will not see
    ASSERT_TRUE(tx.commit().ok());
  }
  {
    auto tx = a.g.begin();
    ASSERT_TRUE(tx.set_rt(q, c, at(3), 30).ok());  // the move, made at pose 2
    ASSERT_TRUE(tx.commit().ok());
  }
  {
    auto tx = b.g.begin();
    ASSERT_TRUE(tx.delete_node(q).ok());  // concurrently, the new parent goes
    ASSERT_TRUE(tx.commit().ok());
  }
  ASSERT_EQ(b.g.rt_edge(c)->pose.translation[0], 1.0);
  std::vector<ChangeBatch> seen;
  b.g.subscribe([&](const ChangeBatch& batch) { seen.push_back(batch); });
  b.receive(a.outbox.back());
  ASSERT_EQ(b.g.rt_parent(c), p);
  EXPECT_EQ(b.g.rt_edge(c)->pose.translation[0], 2.0) << "the pose the move was made at";
  ASSERT_EQ(seen.size(), 1u);
  bool announced = false;
  for (const EdgeChange& e : seen[0].edges)
    if (e.key == EdgeKey{p, c, symbols::rt()} && e.kind == ChangeKind::kUpdated)
      announced = std::find(e.attrs.begin(), e.attrs.end(), symbols::pose()) != e.attrs.end();
  EXPECT_TRUE(announced) << "the merge changed the pose of p -> c without saying so";
  EXPECT_TRUE(b.g.check_invariants().empty());
}

// A fragment that removes a node's id listed under another key (an edge's, as a forger could)
// deletes that node with its data on every replica, whether it held the node, only data written
// to it, or neither yet: no zombie, and the replicas end equal (found by the replication_samples
// fuzzer: a deleted node still held an attribute).
TEST(GraphTest, ANodesIdRemovedUnderAnotherKeyDeletesTheNodeWithItsData) {
  Peer a(1), b(2), c(3);
  NodeId mug = a.add("mug", "mug");
  NodeId table = a.add("table", "table");
  auto tx = a.g.begin();
  ASSERT_TRUE(tx.set(mug, "colour", Value("red")).ok());
  ASSERT_TRUE(tx.commit().ok());
  ASSERT_EQ(a.outbox.size(), 3u);
  b.receive(a.outbox[2]);  // b holds only the attribute written to a mug it has not seen created
  c.receive_all(a);        // c holds everything
  GraphDelta forged;
  forged.origin = a.g.replica();
  forged.seq_lo = forged.seq_hi = 9;
  forged.removed.push_back(mug.dot);
  GraphDelta::EdgeOp e;
  e.key = EdgeKey{table, mug, Symbol("on")};
  e.removed = GraphDelta::Span{0, 1};
  forged.edges.push_back(e);
  auto bytes = encode(forged);
  b.receive(bytes);
  c.receive(bytes);
  b.receive_all(a);  // the creations arrive late at b
  for (Peer* p : {&b, &c}) {
    EXPECT_TRUE(p->g.check_invariants().empty()) << p->g.check_invariants().front();
    EXPECT_FALSE(p->g.has_node(mug));
    EXPECT_EQ(p->g.attr(mug, Symbol("colour")), nullptr);
    EXPECT_TRUE(p->g.has_node(table));
  }
  EXPECT_EQ(b.g.digest(), c.g.digest());
  // The same through the context alone: a forged delta whose context covers the id of a node whose
  // data arrived before its creation deletes that data too.
  Peer d(4);
  NodeId cup = a.add("cup", "cup");
  tx = a.g.begin();
  ASSERT_TRUE(tx.set(cup, "colour", Value("blue")).ok());
  ASSERT_TRUE(tx.commit().ok());
  d.receive(a.outbox.back());
  GraphDelta covering;
  covering.origin = a.g.replica();
  covering.seq_lo = covering.seq_hi = 10;
  covering.context.add(cup.dot);
  covering.edges.push_back(GraphDelta::EdgeOp{EdgeKey{table, cup, Symbol("on")}, {}, {}, {}});
  d.receive(encode(covering));
  EXPECT_TRUE(d.g.check_invariants().empty()) << d.g.check_invariants().front();
  EXPECT_EQ(d.g.attr(cup, Symbol("colour")), nullptr);
}

TEST(GraphTest, DeletingAParentDetachesItsChildren) {
  Peer a(1);
  NodeId world = a.add("world", "world"), robot = a.add("robot", "robot"), arm = a.add("arm", "arm");
  auto tx = a.g.begin();
  ASSERT_TRUE(tx.set_rt(world, robot, at(1)).ok());
  ASSERT_TRUE(tx.set_rt(robot, arm, at(1)).ok());
  ASSERT_TRUE(tx.commit().ok());
  auto tx2 = a.g.begin();
  ASSERT_TRUE(tx2.delete_node(robot).ok());
  ASSERT_TRUE(tx2.commit().ok());
  EXPECT_FALSE(a.g.rt_parent(arm).has_value());
  EXPECT_TRUE(a.g.rt_children(world).empty());
  EXPECT_TRUE(a.g.check_invariants().empty());
}

TEST(GraphTest, EventsReportKindOriginAndAttributes) {
  Peer a(1), b(2);
  std::vector<ChangeBatch> seen;
  b.g.subscribe([&](const ChangeBatch& batch) { seen.push_back(batch); });
  NodeId r = a.add("robot", "robot");
  {
    auto tx = a.g.begin();
    ASSERT_TRUE(tx.set(r, "battery", Value(0.4)).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  b.receive_all(a);
  ASSERT_EQ(seen.size(), 2u);
  EXPECT_FALSE(seen[0].local);
  EXPECT_EQ(seen[0].origin, a.g.replica());
  ASSERT_EQ(seen[0].nodes.size(), 1u);
  EXPECT_EQ(seen[0].nodes[0].kind, ChangeKind::kCreated);
  ASSERT_EQ(seen[1].nodes.size(), 1u);
  EXPECT_EQ(seen[1].nodes[0].kind, ChangeKind::kUpdated);
  EXPECT_EQ(seen[1].nodes[0].attrs, std::vector<Symbol>{Symbol("battery")});
  // Local changes are reported as local.
  seen.clear();
  auto tx = b.g.begin();
  ASSERT_TRUE(tx.delete_node(r).ok());
  ASSERT_TRUE(tx.commit().ok());
  ASSERT_EQ(seen.size(), 1u);
  EXPECT_TRUE(seen[0].local);
  EXPECT_EQ(seen[0].nodes[0].kind, ChangeKind::kDeleted);
}

TEST(GraphTest, StateTransferAndContextDiffConverge) {
  Peer a(1), b(2), c(3);
  NodeId r = a.add("robot", "robot");
  NodeId k = a.add("room", "kitchen");
  b.receive_all(a);
  {
    auto tx = a.g.begin();
    ASSERT_TRUE(tx.insert_edge(r, k, Symbol("in")).ok());
    ASSERT_TRUE(tx.set(r, "battery", Value(0.3)).ok());
    ASSERT_TRUE(tx.commit().ok());
    auto tx2 = a.g.begin();
    ASSERT_TRUE(tx2.delete_node(k).ok());
    ASSERT_TRUE(tx2.commit().ok());
  }
  c.receive_state(a);
  EXPECT_EQ(c.g.digest(), a.g.digest());
  b.receive_diff(a);  // b knew k: the diff must delete it there
  EXPECT_FALSE(b.g.has_node(k));
  EXPECT_EQ(b.g.digest(), a.g.digest());
  EXPECT_TRUE(b.g.check_invariants().empty());
}

}  // namespace
}  // namespace quiver::graph
