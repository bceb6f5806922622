// Translation onto Quiver of RoboComp CORTEX's DSR tests, file tests/graph/graph_operations.cpp
// (robocomp/cortex): SCENARIO "Node insertions, updates and removals". Catch2 runs each nested
// GIVEN / WHEN / THEN section on a fresh graph after re-running the sections above it; each TEST
// here runs the same path (the fixture's steps) and then asserts what that section asserts.
//
// CORTEX runs the scenario under SyncMode::CRDT and SyncMode::LWW; Quiver has one merge semantics.
// The graph is seeded from data/edge_world.json (CORTEX's make_edge_config_file()). DSR's `int`
// attributes are int32 (Value::int32); update_node is a committed transaction.

#include <gtest/gtest.h>

#include <cstdint>
#include <optional>
#include <string>

#include "cortex_graph_fixture.h"

namespace quiver::cortex_tests {
namespace {

class CortexNodeInsertionsUpdatesAndRemovals : public CortexWorldTest {
 protected:
  CortexNodeInsertionsUpdatesAndRemovals() : CortexWorldTest("edge_world.json", ReplicaId{0xC4, 1}) {}
  // GIVEN "A new Node" + THEN "The node is inserted and the graph is bigger": a robot node named
  // robot_8 with attribute att = "value", inserted.
  Result<NodeId> insert_robot_8() { return try_insert_node("robot", "robot_8", {{Symbol("att"), Value("value")}}); }
  // AND_WHEN "The node is updated": int_ = 11 added and the node updated.
  Status update_robot_8() {
    auto id = g.find_node("robot_8");
    if (!id) return make_error(ErrorCode::kNotFound, "robot_8");
    return set_and_commit(*id, "int_", Value::int32(11));
  }
  // AND_WHEN "The node is deleted" (DSR's delete_node by name).
  void delete_robot_8() {
    auto id = g.find_node("robot_8");
    ASSERT_TRUE(id.has_value());
    auto tx = g.begin();
    ASSERT_TRUE(tx.delete_node(*id).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
};

// CORTEX graph_operations.cpp, SCENARIO "Node insertions, updates and removals" /
// GIVEN "A new Node" (REQUIRE_NOTHROW(n.type("robot"))). (a) Quiver takes the type at creation:
// "robot" is accepted.
TEST_F(CortexNodeInsertionsUpdatesAndRemovals, GivenANewNode) {
  auto tx = g.begin();
  auto id = tx.create_node("robot", "robot_8", {{"att", Value("value")}});
  ASSERT_TRUE(id.ok()) << id.error().to_string();
  EXPECT_EQ(tx.ops().size(), 1u);
}

// CORTEX graph_operations.cpp, SCENARIO "Node insertions, updates and removals" /
// THEN "The node is inserted and the graph is bigger". (a)
TEST_F(CortexNodeInsertionsUpdatesAndRemovals, TheNodeIsInsertedAndTheGraphIsBigger) {
  const std::size_t size = g.node_count();
  auto r = insert_robot_8();
  ASSERT_TRUE(r.ok()) << r.error().to_string();
  EXPECT_EQ(size + 1, g.node_count());
}

// CORTEX graph_operations.cpp, SCENARIO "Node insertions, updates and removals" /
// AND_THEN "You can get the node" (after the insertion). (a)
TEST_F(CortexNodeInsertionsUpdatesAndRemovals, YouCanGetTheNode) {
  ASSERT_TRUE(insert_robot_8().ok());
  auto no = g.find_node("robot_8");
  ASSERT_TRUE(no.has_value());
  EXPECT_TRUE(g.has_node(*no));
  EXPECT_TRUE(g.find_node("robot_8").has_value());
}

// CORTEX graph_operations.cpp, SCENARIO "Node insertions, updates and removals" /
// THEN "The requested node is equal to the inserted node". (a) There are no Node copies to compare:
// the node found by name has the inserted id, type, name and attribute.
TEST_F(CortexNodeInsertionsUpdatesAndRemovals, TheRequestedNodeIsEqualToTheInsertedNode) {
  auto inserted = insert_robot_8();
  ASSERT_TRUE(inserted.ok());
  auto node = g.find_node("robot_8");
  ASSERT_TRUE(node.has_value());
  EXPECT_EQ(*node, *inserted);
  EXPECT_EQ(g.type_of(*node).str(), "robot");
  EXPECT_EQ(g.name_of(*node), "robot_8");
  EXPECT_EQ(g.attr_names(*node), std::vector<Symbol>{Symbol("att")});
  EXPECT_EQ(g.get<std::string>(*node, "att").value(), "value");
}

// CORTEX graph_operations.cpp, SCENARIO "Node insertions, updates and removals" /
// AND_WHEN "The node is updated". (a)
TEST_F(CortexNodeInsertionsUpdatesAndRemovals, TheNodeIsUpdated) {
  ASSERT_TRUE(insert_robot_8().ok());
  ASSERT_TRUE(g.find_node("robot_8").has_value());
  Status r = update_robot_8();
  EXPECT_TRUE(r.ok()) << r.error().to_string();
}

// CORTEX graph_operations.cpp, SCENARIO "Node insertions, updates and removals" /
// THEN "The graph size is equal" (after the update). (a)
TEST_F(CortexNodeInsertionsUpdatesAndRemovals, TheGraphSizeIsEqual) {
  ASSERT_TRUE(insert_robot_8().ok());
  const std::size_t size = g.node_count();
  ASSERT_TRUE(update_robot_8().ok());
  EXPECT_EQ(size, g.node_count());
}

// CORTEX graph_operations.cpp, SCENARIO "Node insertions, updates and removals" /
// AND_THEN "You can get the node" (the second section of this title, after the update). (a)
TEST_F(CortexNodeInsertionsUpdatesAndRemovals, YouCanGetTheNodeAfterTheUpdate) {
  ASSERT_TRUE(insert_robot_8().ok());
  ASSERT_TRUE(update_robot_8().ok());
  EXPECT_TRUE(g.find_node("robot_8").has_value());
}

// CORTEX graph_operations.cpp, SCENARIO "Node insertions, updates and removals" /
// THEN "The requested node has the inserted attribute". (a)
TEST_F(CortexNodeInsertionsUpdatesAndRemovals, TheRequestedNodeHasTheInsertedAttribute) {
  ASSERT_TRUE(insert_robot_8().ok());
  ASSERT_TRUE(update_robot_8().ok());
  auto node = g.find_node("robot_8");
  ASSERT_TRUE(node.has_value());
  auto v = g.get<std::int32_t>(*node, "int_");
  ASSERT_TRUE(v.ok()) << v.error().to_string();
  EXPECT_EQ(*v, 11);
}

// CORTEX graph_operations.cpp, SCENARIO "Node insertions, updates and removals" /
// AND_THEN "You can't get or update the node" (after the deletion). (a) DSR's update_node of the
// deleted node throws; Quiver's write to it is refused with kNotFound.
TEST_F(CortexNodeInsertionsUpdatesAndRemovals, YouCantGetOrUpdateTheNode) {
  ASSERT_TRUE(insert_robot_8().ok());
  ASSERT_TRUE(update_robot_8().ok());
  const NodeId node = g.find_node("robot_8").value();
  delete_robot_8();
  auto tx = g.begin();
  Status s = tx.set(node, "int_", Value::int32(12));
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().code, ErrorCode::kNotFound);
  EXPECT_FALSE(g.find_node("robot_8").has_value());
  EXPECT_FALSE(g.has_node(node));
}

// CORTEX graph_operations.cpp, SCENARIO "Node insertions, updates and removals" /
// AND_GIVEN "A deleted node" / THEN "Optional value is empty". (a)
TEST_F(CortexNodeInsertionsUpdatesAndRemovals, OptionalValueIsEmpty) {
  ASSERT_TRUE(insert_robot_8().ok());
  ASSERT_TRUE(update_robot_8().ok());
  delete_robot_8();
  EXPECT_FALSE(g.find_node("robot_8").has_value());
}

}  // namespace
}  // namespace quiver::cortex_tests
