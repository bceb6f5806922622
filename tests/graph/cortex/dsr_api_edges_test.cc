// Translation of RoboComp CORTEX tests/src/test_dsr_api.cpp onto Quiver, its edge and graph-query
// sections: TEST_CASE "Edge operations", "Maps operations", "Node and Edge type checking
// (RUNTIME)" and "Convenience methods". The fixture (CortexDsrApi, the graph every test builds) is
// in dsr_api_fixture.h; docs/dsr-api.md maps each DSR call.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>
#include <optional>
#include <vector>

#include "dsr_api_fixture.h"

namespace quiver::cortex_tests {
namespace {

// ---------------------------------------------------------------------------------------------
// TEST_CASE "Edge operations"

// CORTEX test_dsr_api.cpp, "Edge operations" / "Get an edge that does not exists by id". Class (a).
TEST_F(CortexDsrApi, EdgeOperationsGetAnEdgeThatDoesNotExistsById) {
  EXPECT_FALSE(g.has_edge(absent_id(666666), absent_id(77777), "K"));
  EXPECT_EQ(g.edge_attr(EdgeKey{absent_id(666666), absent_id(77777), Symbol("K")}, "x"), nullptr);
}

// CORTEX test_dsr_api.cpp, "Edge operations" / "Get an edge that does not exists by name".
// Class (a).
TEST_F(CortexDsrApi, EdgeOperationsGetAnEdgeThatDoesNotExistsByName) {
  EXPECT_FALSE(g.find_edge("no existe", "otro no existe", "K").has_value());
}

struct CortexDsrApiEdgeOps : CortexDsrApi {
  NodeId e1, e2;
  void SetUp() override {
    CortexDsrApi::SetUp();
    e1 = create("test_n", "nodeedge1");
    e2 = create("test_n", "nodeedge2");
    ASSERT_TRUE(insert_edge(e1, e2, "test_e").ok());
  }
};

// CORTEX test_dsr_api.cpp, "Edge operations" / "Insert a new edge and get it by name and id".
// Class (a).
TEST_F(CortexDsrApi, EdgeOperationsInsertANewEdgeAndGetItByNameAndId) {
  NodeId id1 = create("test_n", "nodeedge1");
  NodeId id2 = create("test_n", "nodeedge2");
  EXPECT_TRUE(insert_edge(id1, id2, "test_e").ok());
  EXPECT_TRUE(g.has_edge(id1, id2, "test_e"));
  auto by_name = g.find_edge("nodeedge1", "nodeedge2", "test_e");
  ASSERT_TRUE(by_name.has_value());
  EXPECT_EQ(*by_name, (EdgeKey{id1, id2, Symbol("test_e")}));
}

// CORTEX test_dsr_api.cpp, "Edge operations" / "Update existing edge". Class (a): the one
// test_e edge gets a string attribute and is inserted again.
TEST_F(CortexDsrApiEdgeOps, EdgeOperationsUpdateExistingEdge) {
  auto edges = g.edges_of_type("test_e");
  ASSERT_EQ(edges.size(), 1u);
  auto tx = g.begin();
  EXPECT_TRUE(tx.insert_edge(edges[0].from, edges[0].to, Symbol("test_e"), {{Symbol("test_string"), Value("a")}}).ok());
  ASSERT_TRUE(tx.commit().ok());
  EXPECT_EQ(g.get<std::string>(edges[0], "test_string").value_or(""), "a");
}

// CORTEX test_dsr_api.cpp, "Edge operations" / "Delete existing edge by id". Class (a): deleted,
// gone, and inserting it again works.
TEST_F(CortexDsrApiEdgeOps, EdgeOperationsDeleteExistingEdgeById) {
  auto edges = g.edges_of_type("test_e");
  ASSERT_EQ(edges.size(), 1u);
  const EdgeKey e = edges[0];
  {
    auto tx = g.begin();
    EXPECT_TRUE(tx.delete_edge(e.from, e.to, "test_e").ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  EXPECT_FALSE(g.has_edge(e.from, e.to, "test_e"));
  EXPECT_TRUE(insert_edge(e.from, e.to, "test_e").ok());
  EXPECT_TRUE(g.has_edge(e.from, e.to, "test_e"));
}

// CORTEX test_dsr_api.cpp, "Edge operations" / "Delete existing edge by name". Class (a).
TEST_F(CortexDsrApiEdgeOps, EdgeOperationsDeleteExistingEdgeByName) {
  ASSERT_EQ(g.edges_of_type("test_e").size(), 1u);
  auto tx = g.begin();
  EXPECT_TRUE(tx.delete_edge("nodeedge1", "nodeedge2", "test_e").ok());
  ASSERT_TRUE(tx.commit().ok());
  EXPECT_FALSE(g.find_edge("nodeedge1", "nodeedge2", "test_e").has_value());
}

// CORTEX test_dsr_api.cpp, "Edge operations" / "Delete an edge that does not exists". Class (a).
TEST_F(CortexDsrApiEdgeOps, EdgeOperationsDeleteAnEdgeThatDoesNotExists) {
  auto tx = g.begin();
  Status s = tx.delete_edge(absent_id(4), absent_id(5), "test_e");
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().code, ErrorCode::kNotFound);
  Status s2 = tx.delete_edge(e2, e1, "test_e");  // the reverse of the existing one
  EXPECT_FALSE(s2.ok());
}

// ---------------------------------------------------------------------------------------------
// TEST_CASE "Maps operations"

// CORTEX test_dsr_api.cpp, "Maps operations" / "Get id from a name and a name from an id".
// Class (a).
TEST_F(CortexDsrApi, MapsOperationsGetIdFromANameAndANameFromAnId) {
  NodeId r = create("test_n", "nameformaptestnode");
  auto id = g.find_node("nameformaptestnode");
  ASSERT_TRUE(id.has_value());
  EXPECT_EQ(*id, r);
  auto name = g.find_name(r);
  ASSERT_TRUE(name.has_value());
  EXPECT_EQ(*name, "nameformaptestnode");
}

// CORTEX test_dsr_api.cpp, "Maps operations" / "Get id from a name that does not exist". Class (a).
TEST_F(CortexDsrApi, MapsOperationsGetIdFromANameThatDoesNotExist) { EXPECT_FALSE(g.find_node("t_55").has_value()); }

// CORTEX test_dsr_api.cpp, "Maps operations" / "Get name from an id that does not exist".
// Class (a).
TEST_F(CortexDsrApi, MapsOperationsGetNameFromAnIdThatDoesNotExist) {
  EXPECT_FALSE(g.find_name(absent_id(788987)).has_value());
}

// CORTEX test_dsr_api.cpp, "Maps operations" / "Get nodes by type". Class (a).
TEST_F(CortexDsrApi, MapsOperationsGetNodesByType) {
  NodeId r = create("test_n", "nameformaptestnode2");
  auto ve = g.nodes_of_type("test_n");
  EXPECT_FALSE(ve.empty());
  EXPECT_NE(std::find(ve.begin(), ve.end(), r), ve.end());
  EXPECT_TRUE(g.nodes_of_type("no").empty());
}

// CORTEX test_dsr_api.cpp, "Maps operations" / "Get edges by type". Class (a).
TEST_F(CortexDsrApi, MapsOperationsGetEdgesByType) {
  auto ve = g.edges_of_type("RT");
  EXPECT_FALSE(ve.empty());
  EXPECT_TRUE(std::all_of(ve.begin(), ve.end(), [](const EdgeKey& k) { return k.type == graph::symbols::rt(); }));
  EXPECT_TRUE(g.edges_of_type("no").empty());
}

// CORTEX test_dsr_api.cpp, "Maps operations" / "Get edges from/to a node (id)". Class (a): two
// edges into r, none into r2; none out of r, one out of r2; the same set whichever way it is read
// (DSR compares get_edges() with the node's fano). For an id no node has, DSR's get_edges() gives
// no value; Quiver gives no edges and has_node() says false.
TEST_F(CortexDsrApi, MapsOperationsGetEdgesFromToANodeId) {
  NodeId r = create("test_n", "nameformaptestnode21");
  NodeId r2 = create("test_n", "nameformaptestnode22");
  NodeId r3 = create("test_n", "nameformaptestnode23");
  EXPECT_TRUE(insert_edge(r2, r, "test_e").ok());
  EXPECT_TRUE(insert_edge(r3, r, "test_e").ok());
  EXPECT_EQ(g.edges_to(r).size(), 2u);
  EXPECT_TRUE(g.edges_to(r2).empty());
  EXPECT_TRUE(g.has_node(r));
  EXPECT_TRUE(g.edges_from(r).empty());
  EXPECT_FALSE(g.has_node(absent_id(9999999999)));
  EXPECT_TRUE(g.edges_from(absent_id(9999999999)).empty());
  auto out = g.edges_from(r2);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out, g.edges_from(r2, "test_e"));
  EXPECT_EQ(out[0], (EdgeKey{r2, r, Symbol("test_e")}));
}

// CORTEX test_dsr_api.cpp, "Maps operations" / "Get edges from a node that does not exist".
// Class (b): DSR's get_edges() returns no value (an empty optional) for a missing node; Quiver's
// edges_from() returns an empty list and the absence is read with has_node().
TEST_F(CortexDsrApi, MapsOperationsGetEdgesFromANodeThatDoesNotExist) {
  EXPECT_TRUE(g.edges_from(absent_id(45550)).empty());
  EXPECT_FALSE(g.has_node(absent_id(45550)));
}

// CORTEX test_dsr_api.cpp, "Maps operations" / "Get edges from a node that has no edges".
// Class (a): the node exists and has no edges.
TEST_F(CortexDsrApi, MapsOperationsGetEdgesFromANodeThatHasNoEdges) {
  EXPECT_TRUE(g.has_node(lonely));
  EXPECT_TRUE(g.edges_from(lonely).empty());
}

// ---------------------------------------------------------------------------------------------
// TEST_CASE "Node and Edge type checking (RUNTIME)"

// CORTEX test_dsr_api.cpp, "Node and Edge type checking (RUNTIME)" / "Node". Class (a): with the
// registry as Quiver's schema (install_registry()), a "test_n" node is accepted and an
// "invalidtype" one is refused at commit (kPermissionDenied).
TEST_F(CortexDsrApi, TypeCheckingRuntimeNode) {
  ASSERT_NO_FATAL_FAILURE(install_registry());
  {
    auto tx = g.begin();
    ASSERT_TRUE(tx.create_node("test_n", "typed").ok());
    Status s = commit(tx);
    EXPECT_TRUE(s.ok()) << s.error().to_string();
  }
  EXPECT_TRUE(g.find_node("typed").has_value());
  {
    auto tx = g.begin();
    ASSERT_TRUE(tx.create_node("invalidtype", "untyped").ok());
    Status s = commit(tx);
    ASSERT_FALSE(s.ok());
    EXPECT_EQ(s.error().code, ErrorCode::kPermissionDenied);
  }
  EXPECT_FALSE(g.find_node("untyped").has_value());
}

// CORTEX test_dsr_api.cpp, "Node and Edge type checking (RUNTIME)" / "Edge". Class (a): the same
// for edge types: a "test_e" edge is accepted, an "invalidtype" edge refused (kPermissionDenied).
TEST_F(CortexDsrApi, TypeCheckingRuntimeEdge) {
  ASSERT_NO_FATAL_FAILURE(install_registry());
  {
    auto tx = g.begin();
    ASSERT_TRUE(tx.insert_edge(lonely, child, "test_e").ok());
    Status s = commit(tx);
    EXPECT_TRUE(s.ok()) << s.error().to_string();
  }
  EXPECT_TRUE(g.has_edge(lonely, child, "test_e"));
  {
    auto tx = g.begin();
    ASSERT_TRUE(tx.insert_edge(lonely, child, "invalidtype").ok());
    Status s = commit(tx);
    ASSERT_FALSE(s.ok());
    EXPECT_EQ(s.error().code, ErrorCode::kPermissionDenied);
  }
  EXPECT_FALSE(g.has_edge(lonely, child, "invalidtype"));
}

// ---------------------------------------------------------------------------------------------
// TEST_CASE "Convenience methods"

// CORTEX test_dsr_api.cpp, "Convenience methods" / "Get node level". Class (a): DSR's
// get_node_level() is Graph::rt_level(): 1 for node 2 (the root's RT child), nothing for a new
// node in no tree.
TEST_F(CortexDsrApi, ConvenienceGetNodeLevel) {
  ASSERT_TRUE(g.has_node(child));
  std::optional<std::size_t> level = g.rt_level(child);
  ASSERT_TRUE(level.has_value());
  EXPECT_EQ(*level, 1u);

  NodeId in = create("test_n", "unplaced");
  ASSERT_TRUE(g.has_node(in));
  EXPECT_FALSE(g.rt_level(in).has_value());
}

// CORTEX test_dsr_api.cpp, "Convenience methods" / "Get parent id". Class (a).
TEST_F(CortexDsrApi, ConvenienceGetParentId) {
  auto p = g.rt_parent(child);
  ASSERT_TRUE(p.has_value());
  EXPECT_EQ(*p, root);
}

// CORTEX test_dsr_api.cpp, "Convenience methods" / "Get parent node". Class (a): the parent is
// the root; the root has none.
TEST_F(CortexDsrApi, ConvenienceGetParentNode) {
  auto p = g.rt_parent(child);
  ASSERT_TRUE(p.has_value());
  EXPECT_EQ(g.name_of(*p), "root");
  EXPECT_FALSE(g.rt_parent(root).has_value());
}

// CORTEX test_dsr_api.cpp, "Convenience methods" / "get_node_root". Class (a).
TEST_F(CortexDsrApi, ConvenienceGetNodeRoot) {
  EXPECT_EQ(g.find_node("root"), root);
  EXPECT_EQ(g.rt_roots(), std::vector<NodeId>{root});
}

}  // namespace
}  // namespace quiver::cortex_tests
