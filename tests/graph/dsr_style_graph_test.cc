// The DSR-style surface of the graph (docs/dsr-api.md): integer literals as int64, errors that
// name the requested type, string overloads, typed edge attributes, filtered subscriptions and
// the origin's name on change batches.

#include <gtest/gtest.h>

#include "quiver/graph/graph.h"

namespace quiver::graph {
namespace {

ReplicaId rid(std::uint64_t a) { return ReplicaId{a, 1}; }

TEST(ValueApi, IntegerLiteralsAreSixtyFourBit) {
  EXPECT_EQ(Value(4).type(), ValueType::kInt64);
  EXPECT_EQ(Value(-4L).type(), ValueType::kInt64);
  EXPECT_EQ(Value(std::int16_t{4}).type(), ValueType::kInt64);
  EXPECT_EQ(Value(4u).type(), ValueType::kUInt64);
  EXPECT_EQ(Value(std::size_t{4}).type(), ValueType::kUInt64);
  EXPECT_EQ(Value(true).type(), ValueType::kBool);
  EXPECT_EQ(Value(4.0).type(), ValueType::kDouble);
  EXPECT_EQ(Value(4.0f).type(), ValueType::kFloat);
  EXPECT_EQ(Value("x").type(), ValueType::kString);
  EXPECT_EQ(Value::int32(4).type(), ValueType::kInt32);
  EXPECT_EQ(Value::uint32(4).type(), ValueType::kUInt32);
  EXPECT_EQ(*Value(4).get_if<std::int64_t>(), 4);
  EXPECT_EQ(Value(std::int64_t{1} << 40).as<std::int64_t>().value(), std::int64_t{1} << 40);
}

TEST(ValueApi, MismatchNamesBothTypes) {
  auto r = Value("fast").as<std::int64_t>();
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, ErrorCode::kTypeMismatch);
  EXPECT_EQ(r.error().message, "as<int64>(): the value is a string, not an int64");
  EXPECT_EQ(Value::type_name<Vec3f>(), std::string("vec3f"));
  static_assert(value_type_of<double> == ValueType::kDouble);
}

struct Fixture : ::testing::Test {
  Graph g{rid(1)};
  NodeId robot, room, mug;
  void SetUp() override {
    auto tx = g.begin();
    robot = tx.create_node("robot", "robot", {{"speed", 4}, {"label", "r2"}}).value();
    room = tx.create_node("room", "kitchen").value();
    mug = tx.create_node("mug", "mug1", {{"color", "red"}}).value();
    ASSERT_TRUE(tx.insert_edge(robot, room, "in", {{"since", 12}, {"certainty", 0.5}}).ok());
    ASSERT_TRUE(tx.insert_edge(mug, room, "in").ok());
    ASSERT_TRUE(tx.commit().ok());
  }
};

TEST_F(Fixture, TypedNodeGettersNameTypes) {
  EXPECT_EQ(g.get<std::int64_t>(robot, "speed").value(), 4);
  auto wrong = g.get<std::int64_t>(robot, "label");
  ASSERT_FALSE(wrong.ok());
  EXPECT_EQ(wrong.error().code, ErrorCode::kTypeMismatch);
  EXPECT_NE(wrong.error().message.find("get<int64>(): attribute 'label' of node 'robot'"), std::string::npos)
      << wrong.error().message;
  EXPECT_NE(wrong.error().message.find("is a string, not an int64"), std::string::npos) << wrong.error().message;
  auto missing = g.get<double>(robot, "never_written_anywhere");
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error().code, ErrorCode::kNotFound);
  // The lookup of an unknown name does not intern it.
  EXPECT_TRUE(Symbol::find("never_written_anywhere").is_null());
}

TEST_F(Fixture, StringOverloads) {
  EXPECT_TRUE(g.has_edge(robot, room, "in"));
  EXPECT_FALSE(g.has_edge(robot, room, "on"));
  EXPECT_EQ(g.edges_of_type("in").size(), 2u);
  EXPECT_TRUE(g.edges_of_type("type_nobody_used").empty());
  EXPECT_EQ(g.edges_from(robot, "in").size(), 1u);
  EXPECT_EQ(g.edges_to(room, "in").size(), 2u);
  EXPECT_TRUE(g.edges_to(room, "on").empty());
  EXPECT_EQ(g.nodes_of_type("mug").size(), 1u);

  auto tx = g.begin();
  ASSERT_TRUE(tx.delete_edge(mug, room, "in").ok());
  const EdgeKey in{robot, room, Symbol("in")};
  auto edge_removed = tx.remove_edge_attr(in, "certainty");
  ASSERT_TRUE(edge_removed.ok());
  EXPECT_TRUE(*edge_removed) << "the edge had it";
  EXPECT_FALSE(*tx.remove_edge_attr(in, "certainty")) << "gone, as this transaction sees it";
  EXPECT_FALSE(*tx.remove_edge_attr(in, "never_set"));
  EXPECT_TRUE(*tx.remove_edge_attr(in, "since")) << "the replica's, then written again below";
  ASSERT_TRUE(tx.set_edge_attr(in, "since", 13).ok());
  EXPECT_FALSE(tx.remove_edge_attr(EdgeKey{mug, room, Symbol("in")}, "x").ok()) << "deleted in this transaction";
  // As DSR's remove_attrib_local: true when the node had it, false when it had not (here: no
  // longer, as this transaction sees it, or never).
  auto removed = tx.remove_attr(mug, "color");
  ASSERT_TRUE(removed.ok());
  EXPECT_TRUE(*removed);
  EXPECT_FALSE(*tx.remove_attr(mug, "color"));
  EXPECT_FALSE(*tx.remove_attr(mug, "never_set"));
  ASSERT_TRUE(tx.set(mug, "later", 1).ok());
  EXPECT_TRUE(*tx.remove_attr(mug, "later")) << "set earlier in the same transaction";
  EXPECT_FALSE(tx.remove_attr(NodeId{}, "color").ok());
  ASSERT_TRUE(tx.commit().ok());
  EXPECT_FALSE(g.has_edge(mug, room, "in"));
  EXPECT_EQ(g.edges_of_type("in").size(), 1u);
  EXPECT_EQ(g.attr(mug, "color"), nullptr);
  EXPECT_EQ(g.edge_attr(EdgeKey{robot, room, Symbol("in")}, "certainty"), nullptr);
  EXPECT_EQ(g.get<std::int64_t>(in, "since").value(), 13);
}

// DSR's by-name calls: get_edge(from, to, type), insert_or_assign_edge and delete_edge by the
// endpoints' names, and get_name_from_id, which gives nothing for an absent node.
TEST_F(Fixture, ByNameOverloadsAndFindName) {
  ASSERT_TRUE(g.find_edge("robot", "kitchen", "in").has_value());
  EXPECT_EQ(*g.find_edge("robot", "kitchen", "in"), (EdgeKey{robot, room, Symbol("in")}));
  EXPECT_FALSE(g.find_edge("robot", "kitchen", "on").has_value());
  EXPECT_FALSE(g.find_edge("robot", "nowhere", "in").has_value());
  EXPECT_FALSE(g.find_edge("robot", "kitchen", "type_nobody_ever_named").has_value());
  EXPECT_TRUE(Symbol::find("type_nobody_ever_named").is_null()) << "a lookup interns nothing";
  EXPECT_EQ(g.find_name(mug), std::optional<std::string>("mug1"));
  {
    auto tx = g.begin();
    ASSERT_TRUE(tx.insert_edge("mug1", "robot", "near", {{Symbol("d"), Value(0.2)}}).ok());
    ASSERT_TRUE(tx.delete_edge("mug1", "kitchen", "in").ok());
    auto missing = tx.delete_edge("mug1", "garage", "in");
    ASSERT_FALSE(missing.ok());
    EXPECT_EQ(missing.error().code, ErrorCode::kNotFound);
    EXPECT_EQ(missing.error().message, "delete_edge(): no node named 'garage'");
    EXPECT_EQ(tx.insert_edge("ghost", "robot", "near").error().message, "insert_edge(): no node named 'ghost'");
    EXPECT_EQ(tx.delete_edge("mug1", "robot", "never_named_type").error().code, ErrorCode::kNotFound);
    ASSERT_TRUE(tx.delete_node(mug).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  EXPECT_FALSE(g.find_edge("mug1", "kitchen", "in").has_value());
  EXPECT_EQ(g.find_name(mug), std::nullopt) << "deleted: nothing, where name_of() gives \"\"";
  EXPECT_EQ(g.name_of(mug), "");
  EXPECT_EQ(g.find_name(NodeId{}), std::nullopt);
}

// One story for RT edges, as DSR has: set_rt() makes one (it needs a pose); set_edge_attr,
// remove_edge_attr, insert_edge (replacing the attributes) and delete_edge work on it, and
// has_edge/edge_attr read it. Its attributes (rt_covariance, custom) are the child's rt: ones.
TEST_F(Fixture, RtEdgesHoldAttributes) {
  const EdgeKey rt{room, mug, symbols::rt()};
  {
    auto tx = g.begin();
    ASSERT_TRUE(tx.set_rt(room, mug, Pose{}, 1).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  ASSERT_TRUE(g.has_edge(room, mug, "RT"));
  {
    auto tx = g.begin();
    ASSERT_TRUE(tx.set_edge_attr(rt, "rt_covariance", Value(graph::FloatVec{0.1f, 0.2f})).ok());
    ASSERT_TRUE(tx.set_edge_attr(rt, "calibrated", Value(true)).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  EXPECT_EQ(*g.edge_attr(rt, "calibrated"), Value(true));
  EXPECT_EQ(*g.attr(mug, "rt:calibrated"), Value(true)) << "kept on the child, as the importers keep them";
  EXPECT_EQ(g.get<bool>(rt, "calibrated").value(), true);
  std::vector<std::string> names;
  for (Symbol a : g.edge_attr_names(rt)) names.push_back(a.str());
  EXPECT_EQ(names, (std::vector<std::string>{"calibrated", "rt_covariance"}));
  {
    auto tx = g.begin();
    EXPECT_TRUE(*tx.remove_edge_attr(rt, "calibrated"));
    EXPECT_FALSE(*tx.remove_edge_attr(rt, "never_named_attribute_of_rt"));
    // Inserting it again replaces its attributes (rt_covariance goes, offset comes).
    ASSERT_TRUE(tx.insert_edge(room, mug, "RT", {{Symbol("offset"), Value(0.5)}}).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  EXPECT_EQ(g.edge_attr(rt, "calibrated"), nullptr);
  EXPECT_EQ(g.edge_attr(rt, "rt_covariance"), nullptr);
  EXPECT_EQ(*g.edge_attr(rt, "offset"), Value(0.5));
  // Not its parent: no such edge, and insert_edge says how an RT edge is made.
  const EdgeKey wrong{robot, mug, symbols::rt()};
  auto tx = g.begin();
  EXPECT_EQ(tx.set_edge_attr(wrong, "x", Value(1)).error().code, ErrorCode::kNotFound);
  EXPECT_EQ(g.edge_attr(wrong, "offset"), nullptr);
  auto refused = tx.insert_edge(robot, mug, "RT");
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.error().message.find("is made with set_rt(parent, child, pose, stamp)"), std::string::npos)
      << refused.error().message;
  ASSERT_TRUE(tx.delete_edge(room, mug, "RT").ok());
  ASSERT_TRUE(tx.commit().ok());
  EXPECT_FALSE(g.has_edge(room, mug, "RT"));
  EXPECT_EQ(g.edge_attr(rt, "offset"), nullptr) << "no edge: no attribute";
}

TEST_F(Fixture, TypedEdgeGetters) {
  const EdgeKey in{robot, room, Symbol("in")};
  EXPECT_EQ(g.get<std::int64_t>(in, "since").value(), 12);
  EXPECT_EQ(g.get<double>(in, "certainty").value(), 0.5);
  auto wrong = g.get<std::string>(in, "since");
  ASSERT_FALSE(wrong.ok());
  EXPECT_EQ(wrong.error().code, ErrorCode::kTypeMismatch);
  EXPECT_EQ(wrong.error().message,
            "get<string>(): attribute 'since' of edge 'robot' -[in]-> 'kitchen' is an int64, not a string");
  auto missing = g.get<double>(in, "weight");
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error().code, ErrorCode::kNotFound);
  EXPECT_NE(missing.error().message.find("has no attribute 'weight'"), std::string::npos);
  auto no_edge = g.get<double>(EdgeKey{room, robot, Symbol("in")}, "since");
  ASSERT_FALSE(no_edge.ok());
  EXPECT_NE(no_edge.error().message.find("does not exist"), std::string::npos) << no_edge.error().message;
}

TEST_F(Fixture, FilteredSubscriptions) {
  std::vector<ChangeBatch> by_node, by_edge, by_attr, all;
  g.subscribe(ChangeFilter{{"mug"}, {}, {}}, [&](const ChangeBatch& b) { by_node.push_back(b); });
  g.subscribe(ChangeFilter{{}, {"on"}, {}}, [&](const ChangeBatch& b) { by_edge.push_back(b); });
  g.subscribe(ChangeFilter{{}, {}, {"speed"}}, [&](const ChangeBatch& b) { by_attr.push_back(b); });
  g.subscribe(ChangeFilter{}, [&](const ChangeBatch& b) { all.push_back(b); });

  {  // robot's speed: only the attribute filter (and the unfiltered one) hear it
    auto tx = g.begin();
    ASSERT_TRUE(tx.set(robot, "speed", 5).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  {  // a mug on the table: the node-type filter sees the mug, the edge-type filter the edge
    auto tx = g.begin();
    auto table = tx.create_node("table", "table1").value();
    ASSERT_TRUE(tx.set(mug, "color", "blue").ok());
    ASSERT_TRUE(tx.insert_edge(mug, table, "on").ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  ASSERT_EQ(by_attr.size(), 1u);
  ASSERT_EQ(by_attr[0].nodes.size(), 1u);
  EXPECT_EQ(by_attr[0].nodes[0].id, robot);
  ASSERT_EQ(by_node.size(), 1u);
  ASSERT_EQ(by_node[0].nodes.size(), 1u);  // the table is not a mug
  EXPECT_EQ(by_node[0].nodes[0].id, mug);
  EXPECT_TRUE(by_node[0].edges.empty());
  ASSERT_EQ(by_edge.size(), 1u);
  EXPECT_TRUE(by_edge[0].nodes.empty());
  ASSERT_EQ(by_edge[0].edges.size(), 1u);
  EXPECT_EQ(by_edge[0].edges[0].key.type.str(), "on");
  EXPECT_EQ(all.size(), 2u);
}

TEST(OriginName, NamerOrIdFallback) {
  Graph a{rid(1)}, b{rid(2)};
  a.set_delta_sink([&](const GraphDelta& d) { b.merge(d); });
  std::vector<ChangeBatch> seen_a, seen_b;
  a.subscribe([&](const ChangeBatch& x) { seen_a.push_back(x); });
  b.subscribe([&](const ChangeBatch& x) { seen_b.push_back(x); });
  {
    auto tx = a.begin();
    ASSERT_TRUE(tx.create_node("robot", "r").ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  ASSERT_EQ(seen_b.size(), 1u);
  EXPECT_EQ(seen_b[0].origin, rid(1));
  EXPECT_EQ(seen_b[0].origin_name, rid(1).to_string());  // no namer: the id
  b.set_origin_namer([](const ReplicaId& r, std::string& name) { name = r.agent == 1 ? std::string("alice") : r.to_string(); });
  {
    auto tx = a.begin();
    ASSERT_TRUE(tx.create_node("robot", "s").ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  ASSERT_EQ(seen_b.size(), 2u);
  EXPECT_EQ(seen_b[1].origin_name, "alice");
  EXPECT_TRUE(seen_a[1].local);
}

}  // namespace
}  // namespace quiver::graph
