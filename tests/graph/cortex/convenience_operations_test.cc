// Translation onto Quiver of RoboComp CORTEX's DSR tests, file tests/graph/convenience_operations.cpp
// (robocomp/cortex). Each TEST names the CORTEX TEST_CASE / SECTION it keeps the intent of.
//
// CORTEX runs every case under SyncMode::CRDT and SyncMode::LWW; Quiver has one merge semantics,
// so each case runs once. The graph is seeded from data/edge_world.json, the Quiver-format copy of
// CORTEX's make_edge_config_file() (tests/utils.h): DSR node 100 is "root", 150 "room", 200
// "Shadow", with RT edges root -> room -> Shadow.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <optional>
#include <string>

#include "cortex_graph_fixture.h"

namespace quiver::cortex_tests {
namespace {

// An id no node of the graph has: a dot of a replica that never wrote to it.

class CortexConvenience : public CortexWorldTest {
 protected:
  CortexConvenience() : CortexWorldTest("edge_world.json", ReplicaId{0xC1, 1}) {}
  NodeId insert_testtype(std::string_view name) { return insert_node("testtype", name); }
};

using CortexMapsOperations = CortexConvenience;
using CortexConvenienceMethods = CortexConvenience;

// ---- TEST_CASE "Maps operations" ----

// CORTEX convenience_operations.cpp, "Maps operations" / "Get id from a name and a name from an id". (a)
TEST_F(CortexMapsOperations, GetIdFromANameAndANameFromAnId) {
  const std::string file_name = "k3JqZ8wPa1";
  const NodeId r = insert_testtype(file_name);
  ASSERT_FALSE(r.is_null());
  std::optional<NodeId> id = g.find_node(file_name);
  ASSERT_TRUE(id.has_value());
  EXPECT_EQ(*id, r);
  std::optional<std::string> name = g.find_name(r);
  ASSERT_TRUE(name.has_value());
  EXPECT_EQ(*name, file_name);
}

// CORTEX convenience_operations.cpp, "Maps operations" / "Get id from a name that does not exist". (a)
TEST_F(CortexMapsOperations, GetIdFromANameThatDoesNotExist) {
  EXPECT_FALSE(g.find_node("Xq8vLmN2pR").has_value());
}

// CORTEX convenience_operations.cpp, "Maps operations" / "Get name from an id that does not exist". (a)
TEST_F(CortexMapsOperations, GetNameFromAnIdThatDoesNotExist) {
  EXPECT_FALSE(g.find_name(absent_id(4242)).has_value());
}

// CORTEX convenience_operations.cpp, "Maps operations" / "Get nodes by type". (a)
TEST_F(CortexMapsOperations, GetNodesByType) {
  const NodeId r = insert_testtype("testtype_1");
  ASSERT_FALSE(r.is_null());
  auto ve = g.nodes_of_type("testtype");
  ASSERT_FALSE(ve.empty());
  EXPECT_NE(std::find(ve.begin(), ve.end(), r), ve.end());
  EXPECT_TRUE(g.nodes_of_type("pQ7rT2uVw9").empty());
}

// CORTEX convenience_operations.cpp, "Maps operations" / "Get edges by type". (a)
TEST_F(CortexMapsOperations, GetEdgesByType) {
  auto ve = g.edges_of_type("RT");
  ASSERT_FALSE(ve.empty());
  EXPECT_EQ(ve.size(), 2u);
  EXPECT_TRUE(std::all_of(ve.begin(), ve.end(), [](const EdgeKey& e) { return e.type.str() == "RT"; }));
  EXPECT_TRUE(g.edges_of_type("aB3cD4eF5g").empty());
}

// CORTEX convenience_operations.cpp, "Maps operations" / "Get edges to a node (id)". (a)
TEST_F(CortexMapsOperations, GetEdgesToANodeId) {
  EXPECT_TRUE(g.edges_to(root).empty());
  auto ve = g.edges_to(shadow);
  ASSERT_EQ(ve.size(), 1u);
  EXPECT_EQ(ve[0], (EdgeKey{room, shadow, graph::symbols::rt()}));
}

// CORTEX convenience_operations.cpp, "Maps operations" / "Get edges from a node". (a) DSR compares
// get_edges(100) with the node's fano(); Quiver has one way to list a node's outgoing edges.
TEST_F(CortexMapsOperations, GetEdgesFromANode) {
  ASSERT_TRUE(g.has_node(root));
  auto ve = g.edges_from(root);
  ASSERT_EQ(ve.size(), 1u);
  EXPECT_EQ(ve[0], (EdgeKey{root, room, graph::symbols::rt()}));
  EXPECT_EQ(g.edges_from(root, "RT"), ve);
}

// CORTEX convenience_operations.cpp, "Maps operations" / "Get edges from a node that does not
// exist". (b) DSR answers nullopt for an absent node; Quiver's edges_from() answers an empty list
// (as for a node without edges) and has_node() tells the two apart.
TEST_F(CortexMapsOperations, GetEdgesFromANodeThatDoesNotExist) {
  const NodeId missing = absent_id(9001);
  EXPECT_FALSE(g.has_node(missing));
  EXPECT_TRUE(g.edges_from(missing).empty());
}

// CORTEX convenience_operations.cpp, "Maps operations" / "Get edges from a node that has no edges". (a)
TEST_F(CortexMapsOperations, GetEdgesFromANodeThatHasNoEdges) {
  EXPECT_TRUE(g.has_node(shadow));
  EXPECT_TRUE(g.edges_from(shadow).empty());
}

// ---- TEST_CASE "Convenience methods" ----

// CORTEX convenience_operations.cpp, "Convenience methods" / "Get node level". (a) DSR's
// get_node_level() is Graph::rt_level(): 0 for the root, nothing for a new node in no tree.
TEST_F(CortexConvenienceMethods, GetNodeLevel) {
  auto n = g.find_node("root");
  ASSERT_TRUE(n.has_value());
  std::optional<std::size_t> level = g.rt_level(*n);
  ASSERT_TRUE(level.has_value());
  EXPECT_EQ(*level, 0u);

  const NodeId id = insert_testtype("loose_node");
  ASSERT_TRUE(g.has_node(id));
  EXPECT_FALSE(g.rt_level(id).has_value());
}

// CORTEX convenience_operations.cpp, "Convenience methods" / "Get parent id". (a)
TEST_F(CortexConvenienceMethods, GetParentId) {
  auto id = g.rt_parent(room);
  ASSERT_TRUE(id.has_value());
  EXPECT_EQ(*id, root);
}

// CORTEX convenience_operations.cpp, "Convenience methods" / "Get parent node". (a)
TEST_F(CortexConvenienceMethods, GetParentNode) {
  auto p = g.rt_parent(room);
  ASSERT_TRUE(p.has_value());
  EXPECT_EQ(*p, g.find_node("root").value());
  EXPECT_EQ(g.name_of(*p), "root");
  EXPECT_FALSE(g.rt_parent(root).has_value());
}

// CORTEX convenience_operations.cpp, "Convenience methods" / "get_node_root". (a)
TEST_F(CortexConvenienceMethods, GetNodeRoot) {
  auto n2 = g.find_node("root");
  ASSERT_TRUE(n2.has_value());
  EXPECT_EQ(*n2, root);
  EXPECT_EQ(g.rt_roots(), std::vector<NodeId>{root});
}

}  // namespace
}  // namespace quiver::cortex_tests
