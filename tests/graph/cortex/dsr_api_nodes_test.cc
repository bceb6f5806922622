// Translation of RoboComp CORTEX tests/src/test_dsr_api.cpp onto Quiver, its node sections:
// TEST_CASE "Node operations" and SCENARIO "Node insertions, updates and removals". The fixture
// (CortexDsrApi, the graph every test builds) is in dsr_api_fixture.h; docs/dsr-api.md maps each
// DSR call.

#include <gtest/gtest.h>

#include <cstddef>
#include <optional>
#include <string>

#include "dsr_api_fixture.h"

namespace quiver::cortex_tests {
namespace {

// ---------------------------------------------------------------------------------------------
// TEST_CASE "Node operations"

// CORTEX test_dsr_api.cpp, "Node operations" / "Get a node that does not exists by id". Class (a).
TEST_F(CortexDsrApi, NodeOperationsGetANodeThatDoesNotExistsById) {
  EXPECT_FALSE(g.has_node(absent_id(3333333)));
  EXPECT_FALSE(g.find_name(absent_id(3333333)).has_value());
}

// CORTEX test_dsr_api.cpp, "Node operations" / "Get a node that does not exists by name". Class (a).
TEST_F(CortexDsrApi, NodeOperationsGetANodeThatDoesNotExistsByName) { EXPECT_FALSE(g.find_node("nop").has_value()); }

// CORTEX test_dsr_api.cpp, "Node operations" / "Insert a new node and get it by id and name".
// Class (a).
TEST_F(CortexDsrApi, NodeOperationsInsertANewNodeAndGetItByIdAndName) {
  auto tx = g.begin();
  auto id = tx.create_node("test_n", "nodename");
  ASSERT_TRUE(id.ok());
  ASSERT_TRUE(tx.commit().ok());
  EXPECT_TRUE(g.has_node(*id));
  EXPECT_EQ(g.find_node("nodename"), *id);
}

// CORTEX test_dsr_api.cpp, "Node operations" / "Create a node with an invalid type". Class (a):
// DSR refuses (throws) a type missing from its type registry; Quiver's registry is the schema
// (install_registry()), and a node of the undeclared type "aaaaa" is refused at commit with
// kPermissionDenied.
TEST_F(CortexDsrApi, NodeOperationsCreateANodeWithAnInvalidType) {
  ASSERT_NO_FATAL_FAILURE(install_registry());
  auto tx = g.begin();
  ASSERT_TRUE(tx.create_node("aaaaa", "n_bad").ok());
  Status s = commit(tx);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().code, ErrorCode::kPermissionDenied);
  EXPECT_FALSE(g.find_node("n_bad").has_value());
}

// CORTEX test_dsr_api.cpp, "Node operations" / "Update existing node". Class (a): adding `level`
// and updating succeeds.
TEST_F(CortexDsrApi, NodeOperationsUpdateExistingNode) {
  NodeId id = create("test_n", "nodename");
  EXPECT_TRUE(set(id, "level", Value::int32(1)).ok());
  EXPECT_EQ(g.get<std::int32_t>(id, "level").value_or(-1), 1);
}

// CORTEX test_dsr_api.cpp, "Node operations" / "Remove an attribute". Class (a): removing `level`
// says true and it is gone; removing it again says false.
TEST_F(CortexDsrApi, NodeOperationsRemoveAnAttribute) {
  NodeId id = create("test_n", "nodename");
  ASSERT_TRUE(set(id, "level", Value::int32(1)).ok());
  auto first = remove(id, "level");
  ASSERT_TRUE(first.ok());
  EXPECT_TRUE(*first);
  EXPECT_EQ(g.attr(id, "level"), nullptr);
  auto second = remove(id, "level");
  ASSERT_TRUE(second.ok());
  EXPECT_FALSE(*second);
}

// CORTEX test_dsr_api.cpp, "Node operations" / "Update an existent node with different name".
// Class (b): DSR's update_node throws when the copy's name differs. Quiver has no call that
// renames a node (writes name attributes, never the node); an attribute called "name" is an
// ordinary attribute: the node keeps answering to "nodename" and nothing answers to "test2".
TEST_F(CortexDsrApi, NodeOperationsUpdateAnExistentNodeWithDifferentName) {
  NodeId id = create("test_n", "nodename");
  ASSERT_TRUE(set(id, "name", Value("test2")).ok());
  EXPECT_EQ(g.find_node("nodename"), id);
  EXPECT_FALSE(g.find_node("test2").has_value());
  EXPECT_EQ(g.name_of(id), "nodename");
}

// CORTEX test_dsr_api.cpp, "Node operations" / "Update an existent node with different id".
// Class (a): writing to an id no node has is refused (DSR throws; Quiver returns kNotFound).
TEST_F(CortexDsrApi, NodeOperationsUpdateAnExistentNodeWithDifferentId) {
  create("test_n", "nodename");
  Status s = set(absent_id(7500166), "level", Value::int32(1));
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().code, ErrorCode::kNotFound);
}

// CORTEX test_dsr_api.cpp, "Node operations" / "Delete existing node by id". Class (a).
TEST_F(CortexDsrApi, NodeOperationsDeleteExistingNodeById) {
  NodeId id = create("test_n", "nodename");
  auto tx = g.begin();
  EXPECT_TRUE(tx.delete_node(id).ok());
  ASSERT_TRUE(tx.commit().ok());
  EXPECT_FALSE(g.find_node("nodename").has_value());
}

// CORTEX test_dsr_api.cpp, "Node operations" / "Delete existing node by name". Class (a): by
// name is find_node() then delete_node().
TEST_F(CortexDsrApi, NodeOperationsDeleteExistingNodeByName) {
  NodeId id = create("test_n", "nodenewname");
  auto found = g.find_node("nodenewname");
  ASSERT_TRUE(found.has_value());
  auto tx = g.begin();
  EXPECT_TRUE(tx.delete_node(*found).ok());
  ASSERT_TRUE(tx.commit().ok());
  EXPECT_FALSE(g.has_node(id));
}

// CORTEX test_dsr_api.cpp, "Node operations" / "Delete a node that does not exists by id".
// Class (a).
TEST_F(CortexDsrApi, NodeOperationsDeleteANodeThatDoesNotExistsById) {
  auto tx = g.begin();
  Status s = tx.delete_node(absent_id(75000));
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().code, ErrorCode::kNotFound);
}

// CORTEX test_dsr_api.cpp, "Node operations" / "Create a node with an user defined name".
// Class (a): the name is the caller's (the id DSR's test also sets is replaced by insert_node;
// Quiver's id is the creation's dot).
TEST_F(CortexDsrApi, NodeOperationsCreateANodeWithAnUserDefinedName) {
  auto tx = g.begin();
  auto id = tx.create_node("test_n", "NODE_NAME");
  ASSERT_TRUE(id.ok());
  ASSERT_TRUE(tx.commit().ok());
  EXPECT_EQ(g.find_node("NODE_NAME"), *id);
}

// ---------------------------------------------------------------------------------------------
// SCENARIO "Node insertions, updates and removals". GIVEN a new node "robot_8" (type robot, with
// test_string = "value").

struct CortexDsrApiScenario : CortexDsrApi {
  std::optional<NodeId> robot8;
  void insert_robot8() {
    auto tx = g.begin();
    auto id = tx.create_node("robot", "robot_8", {{"test_string", Value("value")}});
    ASSERT_TRUE(id.ok());
    ASSERT_TRUE(tx.commit().ok());
    robot8 = *id;
  }
};

// CORTEX test_dsr_api.cpp, SCENARIO "Node insertions, updates and removals" / WHEN "When we
// insert a new node" / THEN "The node is inserted and the graph is bigger". Class (a).
TEST_F(CortexDsrApiScenario, ScenarioTheNodeIsInsertedAndTheGraphIsBigger) {
  const std::size_t size = g.node_count();
  insert_robot8();
  EXPECT_EQ(g.node_count(), size + 1);
}

// CORTEX test_dsr_api.cpp, SCENARIO "Node insertions, updates and removals" / WHEN "When we
// insert a new node" / THEN "You can get the node" (and "The requested node is equal to the
// inserted node"). Class (a): it is found by name, with its type and attribute, and two reads
// agree.
TEST_F(CortexDsrApiScenario, ScenarioInsertedYouCanGetTheNode) {
  insert_robot8();
  auto no = g.find_node("robot_8");
  ASSERT_TRUE(no.has_value());
  auto node = g.find_node("robot_8");
  ASSERT_TRUE(node.has_value());
  EXPECT_EQ(*node, *no);
  EXPECT_EQ(*node, *robot8);
  EXPECT_EQ(g.type_of(*node), Symbol("robot"));
  EXPECT_EQ(g.get<std::string>(*node, "test_string").value_or(""), "value");
}

// CORTEX test_dsr_api.cpp, SCENARIO "Node insertions, updates and removals" / AND_WHEN "The node
// is updated" / THEN "The graph size is equal". Class (a).
TEST_F(CortexDsrApiScenario, ScenarioUpdatedTheGraphSizeIsEqual) {
  insert_robot8();
  const std::size_t size = g.node_count();
  EXPECT_TRUE(set(*robot8, "test_int", Value::int32(11)).ok());
  EXPECT_EQ(g.node_count(), size);
}

// CORTEX test_dsr_api.cpp, SCENARIO "Node insertions, updates and removals" / AND_WHEN "The node
// is updated" / THEN "You can get the node" (and "The requested node has the inserted
// attribute"). Class (a).
TEST_F(CortexDsrApiScenario, ScenarioUpdatedYouCanGetTheNode) {
  insert_robot8();
  ASSERT_TRUE(set(*robot8, "test_int", Value::int32(11)).ok());
  auto node = g.find_node("robot_8");
  ASSERT_TRUE(node.has_value());
  EXPECT_EQ(g.get<std::int32_t>(*node, "test_int").value_or(-1), 11);
}

// CORTEX test_dsr_api.cpp, SCENARIO "Node insertions, updates and removals" / AND_WHEN "The node
// is deleted" / THEN "You can't get or update the node". Class (a): an update is refused
// (kNotFound; DSR throws) and the name finds nothing.
TEST_F(CortexDsrApiScenario, ScenarioDeletedYouCantGetOrUpdateTheNode) {
  insert_robot8();
  {
    auto tx = g.begin();
    ASSERT_TRUE(tx.delete_node(*g.find_node("robot_8")).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  Status s = set(*robot8, "test_int", Value::int32(12));
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().code, ErrorCode::kNotFound);
  EXPECT_FALSE(g.find_node("robot_8").has_value());
}

// CORTEX test_dsr_api.cpp, SCENARIO "Node insertions, updates and removals" / GIVEN "A deleted
// node" / THEN "Optional value is empty". Class (a).
TEST_F(CortexDsrApiScenario, ScenarioADeletedNodeOptionalValueIsEmpty) {
  insert_robot8();
  {
    auto tx = g.begin();
    ASSERT_TRUE(tx.delete_node(*robot8).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  EXPECT_FALSE(g.find_node("robot_8").has_value());
  EXPECT_FALSE(g.has_node(*robot8));
}

}  // namespace
}  // namespace quiver::cortex_tests
