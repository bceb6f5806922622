// Translation of RoboComp CORTEX tests/src/test_dsr_api.cpp onto Quiver (docs/dsr-api.md maps
// each DSR call).
//
// CORTEX's sections share one DSRGraph loaded from testfiles/example.json (node 1 the root, node
// 2 its RT child) and lean on what earlier sections left behind. Here every test builds its own
// graph with the same shape (CortexDsrApi fixture): "root" (DSR's node 1) with an RT child "child"
// (node 2), and "lonely", a node without edges (node 1000); what a section relied on from an
// earlier one is set up in the test. DSR's registered attribute types map to Quiver's value types
// (test_int: int32, test_uint: uint32, ...). DSR reports errors by exceptions or false/nullopt;
// Quiver by Status/Result values (an error code) or nullopt.

#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "quiver/agents/rules/schema/schema.h"
#include "quiver/agents/rules/schema/schema_admission.h"
#include "quiver/graph/graph.h"

namespace quiver::cortex_tests {
namespace {

using graph::Bytes;
using graph::EdgeKey;
using graph::FloatVec;
using graph::Graph;
using graph::NodeId;
using graph::Pose;
using graph::ReplicaId;
using graph::Symbol;
using graph::UInt64Vec;
using graph::Value;
using graph::Vec2f;
using graph::Vec3f;
using graph::Vec4f;
using graph::Vec6f;

// An id no node has (DSR's 3333333, 75000, 788987...).
NodeId absent_id(std::uint64_t counter) { return NodeId{graph::Dot{ReplicaId{777, 1}, counter}}; }

struct CortexDsrApi : ::testing::Test {
  Graph g{ReplicaId{1111, 1}};
  NodeId root, child, lonely;

  void SetUp() override {
    auto tx = g.begin();
    root = tx.create_node("world", "root").value();
    child = tx.create_node("robot", "child").value();
    lonely = tx.create_node("test_n", "lonely").value();
    ASSERT_TRUE(tx.set_rt(root, child, Pose::identity(), 1).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  NodeId create(const std::string& type, const std::string& name) {
    auto tx = g.begin();
    auto id = tx.create_node(type, name);
    EXPECT_TRUE(id.ok()) << id.error().to_string();
    EXPECT_TRUE(tx.commit().ok());
    return id.value_or(NodeId{});
  }
  // DSR's add_or_modify_attrib_local + update_node.
  Status set(NodeId id, std::string_view attr, Value v) {
    auto tx = g.begin();
    Status s = tx.set(id, attr, std::move(v));
    if (!s.ok()) return s;
    auto c = tx.commit();
    if (!c.ok()) return c.error();
    return Status{};
  }
  Result<bool> remove(NodeId id, std::string_view attr) {
    auto tx = g.begin();
    auto r = tx.remove_attr(id, attr);
    EXPECT_TRUE(tx.commit().ok());
    return r;
  }
  Status insert_edge(NodeId from, NodeId to, std::string_view type) {
    auto tx = g.begin();
    Status s = tx.insert_edge(from, to, type);
    if (!s.ok()) return s;
    auto c = tx.commit();
    return c.ok() ? Status{} : Status(c.error());
  }
  EdgeKey rt_key() const { return EdgeKey{root, child, graph::symbols::rt()}; }
  // DSR's type registry (built-in "world" and "robot", the file's REGISTER_NODE_TYPE(test_n) and
  // REGISTER_EDGE_TYPE(test_e), and "RT") as Quiver's schema (docs/schema.md), checked on every
  // commit of `g`: a node or edge of an undeclared type is refused with kPermissionDenied.
  void install_registry() {
    auto parsed = agents::schema::Schema::parse(
        R"({"quiver_schema": 1, "node_types": {"world": {}, "robot": {}, "test_n": {}},
            "edge_types": {"test_e": {}, "RT": {}}})",
        "cortex_registry");
    ASSERT_TRUE(parsed.ok()) << parsed.error().to_string();
    auto registry = std::make_shared<const agents::schema::Schema>(*parsed);
    agents::schema::SchemaAdmission adm(registry, nullptr);
    g.set_permission_check(adm.commit_check(g.replica().agent));
    g.set_type_change_check(adm.type_change_check());
  }
  // A transaction's commit as a Status.
  static Status commit(graph::Transaction& tx) {
    auto c = tx.commit();
    return c.ok() ? Status{} : Status(c.error());
  }
};

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
// TEST_CASE "Attributes operations (Compile time type-check)"

// CORTEX test_dsr_api.cpp, "Attributes operations (Compile time type-check)" / "Insert attribute
// (node) and insert node in G". Class (a).
TEST_F(CortexDsrApi, AttributesInsertAttributeNodeAndInsertNodeInG) {
  EXPECT_TRUE(set(root, "test_int", Value::int32(123)).ok());
  EXPECT_NE(g.attr(root, "test_int"), nullptr);
}

// CORTEX test_dsr_api.cpp, "Attributes operations (Compile time type-check)" / "Insert an string
// attribute and update G". Class (a).
TEST_F(CortexDsrApi, AttributesInsertAnStringAttributeAndUpdateG) {
  EXPECT_TRUE(set(root, "test_string", Value("string att")).ok());
  EXPECT_NE(g.attr(root, "test_string"), nullptr);
  EXPECT_TRUE(set(root, "test_string", Value("string att")).ok());  // updating again succeeds
}

// CORTEX test_dsr_api.cpp, "Attributes operations (Compile time type-check)" / "Insert attribute
// (edge) and insert in G". Class (a): an attribute on the RT edge root -> child.
TEST_F(CortexDsrApi, AttributesInsertAttributeEdgeAndInsertInG) {
  ASSERT_TRUE(g.has_edge(root, child, "RT"));
  auto tx = g.begin();
  EXPECT_TRUE(tx.set_edge_attr(rt_key(), "test_int", Value::int32(123)).ok());
  ASSERT_TRUE(tx.commit().ok());
  EXPECT_NE(g.edge_attr(rt_key(), "test_int"), nullptr);
  EXPECT_EQ(g.get<std::int32_t>(rt_key(), "test_int").value_or(-1), 123);
}

// CORTEX test_dsr_api.cpp, "Attributes operations (Compile time type-check)" / "Update attribute
// and update G". Class (a).
TEST_F(CortexDsrApi, AttributesUpdateAttributeAndUpdateG) {
  ASSERT_TRUE(set(root, "test_int", Value::int32(123)).ok());
  EXPECT_TRUE(set(root, "test_int", Value::int32(125)).ok());
  EXPECT_EQ(g.get<std::int32_t>(root, "test_int").value_or(-1), 125);
}

// CORTEX test_dsr_api.cpp, "Attributes operations (Compile time type-check)" / "Get attribute by
// name". Class (a).
TEST_F(CortexDsrApi, AttributesGetAttributeByName) {
  ASSERT_TRUE(set(root, "test_int", Value::int32(125)).ok());
  auto att = g.get<std::int32_t>(root, "test_int");
  ASSERT_TRUE(att.ok());
  EXPECT_EQ(*att, 125);
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

// ---------------------------------------------------------------------------------------------
// TEST_CASE "Attributes operations II (Runtime time type-check)"

// CORTEX test_dsr_api.cpp, "Attributes operations II (Runtime time type-check)" / "Insert an
// attribute". Class (a): an int32 is written; a float over it is refused (DSR throws; Quiver
// returns kTypeMismatch) and the value stays.
TEST_F(CortexDsrApi, AttributesRuntimeInsertAnAttribute) {
  EXPECT_TRUE(set(root, "test_int", Value::int32(133)).ok());
  EXPECT_EQ(g.get<std::int32_t>(root, "test_int").value_or(-1), 133);
  Status s = set(root, "test_int", Value(133.0f));
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().code, ErrorCode::kTypeMismatch);
  EXPECT_EQ(g.get<std::int32_t>(root, "test_int").value_or(-1), 133);
}

// CORTEX test_dsr_api.cpp, "Attributes operations II (Runtime time type-check)" / "Modify an
// attribute". Class (a).
TEST_F(CortexDsrApi, AttributesRuntimeModifyAnAttribute) {
  ASSERT_TRUE(set(root, "test_int", Value::int32(133)).ok());
  EXPECT_TRUE(set(root, "test_int", Value::int32(111)).ok());
  EXPECT_EQ(g.get<std::int32_t>(root, "test_int").value_or(-1), 111);
}

// CORTEX test_dsr_api.cpp, "Attributes operations II (Runtime time type-check)" / "Update
// attribute". Class (a): the value written is the value read, by name and by typed getter.
TEST_F(CortexDsrApi, AttributesRuntimeUpdateAttribute) {
  ASSERT_TRUE(set(root, "test_int", Value::int32(111)).ok());
  EXPECT_TRUE(set(root, "test_int", Value::int32(177)).ok());
  const Value* v = g.attr(root, "test_int");
  ASSERT_NE(v, nullptr);
  EXPECT_EQ(*v, Value::int32(177));
  EXPECT_EQ(g.get<std::int32_t>(root, "test_int").value_or(-1), 177);
}

// CORTEX test_dsr_api.cpp, "Attributes operations II (Runtime time type-check)" / "Remove an
// attribute". Class (a).
TEST_F(CortexDsrApi, AttributesRuntimeRemoveAnAttribute) {
  ASSERT_TRUE(set(root, "test_int", Value::int32(177)).ok());
  auto r = remove(root, "test_int");
  ASSERT_TRUE(r.ok());
  EXPECT_TRUE(*r);
  EXPECT_EQ(g.attr(root, "test_int"), nullptr);
}

// CORTEX test_dsr_api.cpp, "Attributes operations II (Runtime time type-check)" / "Insert
// attribute (edge) and insert in G". Class (a).
TEST_F(CortexDsrApi, AttributesRuntimeInsertAttributeEdgeAndInsertInG) {
  auto tx = g.begin();
  EXPECT_TRUE(tx.set_edge_attr(rt_key(), "new_int", Value::int32(123)).ok());
  ASSERT_TRUE(tx.commit().ok());
  auto names = g.edge_attr_names(rt_key());
  EXPECT_NE(std::find(names.begin(), names.end(), Symbol("new_int")), names.end());
}

// ---------------------------------------------------------------------------------------------
// TEST_CASE "Other attribute operations and checks"

// CORTEX test_dsr_api.cpp, "Other attribute operations and checks" / "Get attribute timestamp".
// Class (b): attributes carry no wall-clock timestamp (docs/dsr-api.md, "Not carried over"); what
// each value carries is the dot of the write that made it: this replica's, within the counters
// the commit published.
TEST_F(CortexDsrApi, OtherGetAttributeTimestamp) {
  auto tx = g.begin();
  ASSERT_TRUE(tx.set(root, "test_string", Value("string att")).ok());
  auto info = tx.commit();
  ASSERT_TRUE(info.ok());
  auto values = g.attr_values(root, Symbol("test_string"));
  ASSERT_EQ(values.size(), 1u);
  EXPECT_EQ(values[0].dot.replica, g.replica());
  EXPECT_GE(values[0].dot.counter, info->first_counter);
  EXPECT_LE(values[0].dot.counter, info->last_counter);
}

// CORTEX test_dsr_api.cpp, "Other attribute operations and checks" / "Get attribute by name using
// only the id (no references)". Class (a): read by id (Quiver always reads by id).
TEST_F(CortexDsrApi, OtherGetAttributeByNameUsingOnlyTheIdNoReferences) {
  ASSERT_TRUE(set(root, "test_string", Value("string att")).ok());
  auto by_id = g.get<std::string>(root, "test_string");
  auto by_name = g.get<std::string>(*g.find_node("root"), "test_string");
  ASSERT_TRUE(by_id.ok());
  ASSERT_TRUE(by_name.ok());
  EXPECT_EQ(*by_id, *by_name);
  EXPECT_EQ(*by_id, "string att");
}

// CORTEX test_dsr_api.cpp, "Other attribute operations and checks" / "In add_or_modify_attrib_local,
// we can pass a reference or move the value". Class (a).
TEST_F(CortexDsrApi, OtherInAddOrModifyAttribLocalWeCanPassAReferenceOrMoveTheValue) {
  std::string stratt("string att lvalue");
  std::string strattmove("string att rvalue");
  ASSERT_TRUE(set(root, "test_string", stratt).ok());
  EXPECT_EQ(g.get<std::string>(root, "test_string").value_or(""), stratt);
  ASSERT_TRUE(set(root, "test_string", std::move(strattmove)).ok());
  EXPECT_EQ(g.get<std::string>(root, "test_string").value_or(""), "string att rvalue");
}

// CORTEX test_dsr_api.cpp, "Other attribute operations and checks" /
// "runtime_checked_add_or_modify_attrib_local is equivalent to add_or_modify_attrib_local".
// Class (a): DSR's add_or_modify_attrib_local is tx.set() with the attribute's interned Symbol
// (DSR's compile-time name); its runtime_checked_ form is tx.set() with the name as a run-time
// string. Both write (and type-check) alike.
TEST_F(CortexDsrApi, OtherRuntimeCheckedAddOrModifyAttribLocalIsEquivalentToAddOrModifyAttribLocal) {
  const std::string stratt("string att lvalue");
  {
    auto tx = g.begin();
    ASSERT_TRUE(tx.set(root, Symbol("test_string"), Value(stratt)).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  EXPECT_EQ(g.get<std::string>(root, "test_string").value_or(""), stratt);
  {
    const std::string runtime_name{"test_string"};
    auto tx = g.begin();
    EXPECT_TRUE(tx.set(root, std::string_view(runtime_name), Value(stratt)).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  EXPECT_EQ(g.get<std::string>(root, "test_string").value_or(""), stratt);
}

// DSR's get_attrib_by_name() on the local Node copy before update_node(): the value the open
// transaction (Quiver's local copy) last wrote to the attribute, or null if it wrote none.
const Value* written_in(const graph::Transaction& tx, NodeId id, Symbol attr) {
  for (auto op = tx.ops().rbegin(); op != tx.ops().rend(); ++op)
    if (op->kind == graph::TxnOp::Kind::kSetAttr && op->node == id && op->attr == attr) return &op->value;
  return nullptr;
}

// CORTEX test_dsr_api.cpp, "Other attribute operations and checks" / "add_attrib_local is
// equivalent to runtime_checked_add_attrib_local". Class (a): DSR's add_attrib_local is tx.add();
// its runtime_checked_ form is the same call with the Symbol made from a run-time string. A
// second add in the same local copy (transaction) is refused (kAlreadyExists), as DSR's returns
// false.
TEST_F(CortexDsrApi, OtherAddAttribLocalIsEquivalentToRuntimeCheckedAddAttribLocal) {
  const std::string stratt("string att");
  ASSERT_TRUE(remove(root, "test_string").ok());
  EXPECT_FALSE(g.get<std::string>(root, "test_string").ok());
  {
    auto tx = g.begin();
    EXPECT_TRUE(tx.add(root, Symbol("test_string"), Value(stratt)).ok());
    Status again = tx.add(root, Symbol("test_string"), Value(stratt));
    ASSERT_FALSE(again.ok());
    EXPECT_EQ(again.error().code, ErrorCode::kAlreadyExists);
    ASSERT_TRUE(tx.commit().ok());
  }
  auto value1 = g.get<std::string>(root, "test_string");
  ASSERT_TRUE(value1.ok());

  ASSERT_TRUE(remove(root, "test_string").ok());
  EXPECT_FALSE(g.get<std::string>(root, "test_string").ok());
  {
    const std::string runtime_name{"test_string"};
    auto tx = g.begin();
    EXPECT_TRUE(tx.add(root, Symbol(runtime_name), Value(stratt)).ok());
    Status again = tx.add(root, Symbol(runtime_name), Value(stratt));
    ASSERT_FALSE(again.ok());
    EXPECT_EQ(again.error().code, ErrorCode::kAlreadyExists);
    ASSERT_TRUE(tx.commit().ok());
  }
  auto value2 = g.get<std::string>(root, "test_string");
  ASSERT_TRUE(value2.ok());
  EXPECT_EQ(*value1, *value2);
}

// CORTEX test_dsr_api.cpp, "Other attribute operations and checks" / "modify_attrib_local is
// equivalent to runtime_checked_modify_attrib_local". Class (a): DSR's modify_attrib_local is
// tx.modify(): refused (kNotFound) for an attribute the node lacks, accepted once an add earlier in
// the same local copy (transaction) gave it; the runtime_checked_ form is the same call with the
// Symbol made from a run-time string. DSR reads the local copy before update_node(); here that
// is what the open transaction wrote (written_in()).
TEST_F(CortexDsrApi, OtherModifyAttribLocalIsEquivalentToRuntimeCheckedModifyAttribLocal) {
  const std::string stratt("string att");
  const Symbol attr("test_string");
  const std::string runtime_name{"test_string"};
  std::optional<std::string> values[2];
  for (bool runtime_checked : {false, true}) {
    SCOPED_TRACE(runtime_checked ? "runtime_checked_modify_attrib_local" : "modify_attrib_local");
    const Symbol modified = runtime_checked ? Symbol(runtime_name) : attr;
    ASSERT_TRUE(remove(root, "test_string").ok());
    EXPECT_FALSE(g.get<std::string>(root, "test_string").ok());
    auto tx = g.begin();
    Status missing = tx.modify(root, modified, Value(stratt));
    ASSERT_FALSE(missing.ok());
    EXPECT_EQ(missing.error().code, ErrorCode::kNotFound);
    EXPECT_TRUE(tx.add(root, attr, Value("initial_value")).ok());
    ASSERT_NE(written_in(tx, root, attr), nullptr);
    EXPECT_EQ(*written_in(tx, root, attr), Value("initial_value"));
    EXPECT_TRUE(tx.modify(root, modified, Value(stratt)).ok());
    ASSERT_NE(written_in(tx, root, attr), nullptr);
    EXPECT_EQ(*written_in(tx, root, attr), Value(stratt));
    ASSERT_TRUE(tx.commit().ok());
    auto value = g.get<std::string>(root, "test_string");
    ASSERT_TRUE(value.ok());
    values[runtime_checked] = *value;
  }
  EXPECT_EQ(values[0], values[1]);
}

// ---------------------------------------------------------------------------------------------
// TEST_CASE "Native types in attributes". Each "Insert" section writes an attribute of one type
// to node 1 and compares it read from two fetches of the node; each "Get" section reads it with
// the typed getter. Class (a) for all.

template <class T>
void insert_native(CortexDsrApi& t, const char* name, const T& v) {
  ASSERT_TRUE(t.set(t.root, name, Value(v)).ok());
  ASSERT_NE(t.g.attr(t.root, name), nullptr);
  auto first = t.g.get<T>(t.root, name);
  auto second = t.g.get<T>(*t.g.find_node("root"), name);
  ASSERT_TRUE(first.ok());
  ASSERT_TRUE(second.ok());
  EXPECT_EQ(*first, *second);
  EXPECT_EQ(*first, v);
}
template <class T>
void get_native(CortexDsrApi& t, const char* name, const T& v) {
  ASSERT_TRUE(t.set(t.root, name, Value(v)).ok());
  auto st = t.g.get<T>(t.root, name);
  ASSERT_TRUE(st.ok()) << st.error().to_string();
  EXPECT_EQ(*st, v);
}

// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Insert a string attribute".
TEST_F(CortexDsrApi, NativeTypesInsertAStringAttribute) { insert_native<std::string>(*this, "test_string", "string att"); }
// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Get a string attribute".
TEST_F(CortexDsrApi, NativeTypesGetAStringAttribute) { get_native<std::string>(*this, "test_string", "string att"); }

// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Insert an int32 attribute".
TEST_F(CortexDsrApi, NativeTypesInsertAnInt32Attribute) {
  ASSERT_TRUE(set(root, "test_int", Value::int32(11)).ok());
  EXPECT_EQ(g.get<std::int32_t>(root, "test_int").value_or(-1), 11);
  EXPECT_EQ(g.attr(root, "test_int")->type(), graph::ValueType::kInt32);
}
// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Get an int32 attribute".
TEST_F(CortexDsrApi, NativeTypesGetAnInt32Attribute) {
  ASSERT_TRUE(set(root, "test_int", Value::int32(11)).ok());
  EXPECT_TRUE(g.get<std::int32_t>(root, "test_int").ok());
}

// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Insert an uint32 attribute".
TEST_F(CortexDsrApi, NativeTypesInsertAnUint32Attribute) {
  ASSERT_TRUE(set(root, "test_uint", Value::uint32(11u)).ok());
  EXPECT_EQ(g.get<std::uint32_t>(root, "test_uint").value_or(0), 11u);
  EXPECT_EQ(g.attr(root, "test_uint")->type(), graph::ValueType::kUInt32);
}
// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Get an uint32 attribute".
TEST_F(CortexDsrApi, NativeTypesGetAnUint32Attribute) {
  ASSERT_TRUE(set(root, "test_uint", Value::uint32(11u)).ok());
  EXPECT_TRUE(g.get<std::uint32_t>(root, "test_uint").ok());
}

// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Insert an uint64 attribute".
TEST_F(CortexDsrApi, NativeTypesInsertAnUint64Attribute) { insert_native<std::uint64_t>(*this, "test_uint64", 1u); }
// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Get an uint64 attribute".
TEST_F(CortexDsrApi, NativeTypesGetAnUint64Attribute) { get_native<std::uint64_t>(*this, "test_uint64", 1u); }

// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Insert a float attribute".
TEST_F(CortexDsrApi, NativeTypesInsertAFloatAttribute) { insert_native<float>(*this, "test_float", 11.0f); }
// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Get a float attribute".
TEST_F(CortexDsrApi, NativeTypesGetAFloatAttribute) { get_native<float>(*this, "test_float", 11.0f); }

// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Insert a float_vector attribute".
TEST_F(CortexDsrApi, NativeTypesInsertAFloatVectorAttribute) {
  insert_native<FloatVec>(*this, "test_vec_float", FloatVec{11.0f, 167.23f, 55.66f});
}
// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Get a float_vector attribute".
TEST_F(CortexDsrApi, NativeTypesGetAFloatVectorAttribute) {
  get_native<FloatVec>(*this, "test_vec_float", FloatVec{11.0f, 167.23f, 55.66f});
}

// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Insert a bool attribute".
TEST_F(CortexDsrApi, NativeTypesInsertABoolAttribute) { insert_native<bool>(*this, "test_bool", true); }
// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Get a bool attribute".
TEST_F(CortexDsrApi, NativeTypesGetABoolAttribute) { get_native<bool>(*this, "test_bool", true); }

// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Insert a byte_vector attribute"
// (the vector<uint8_t> one).
TEST_F(CortexDsrApi, NativeTypesInsertAByteVectorAttribute) { insert_native<Bytes>(*this, "test_vec_byte", Bytes{11, 167, 55}); }
// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Get a byte_vector attribute" (uint8_t).
TEST_F(CortexDsrApi, NativeTypesGetAByteVectorAttribute) { get_native<Bytes>(*this, "test_vec_byte", Bytes{11, 167, 55}); }

// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Insert a double attribute".
TEST_F(CortexDsrApi, NativeTypesInsertADoubleAttribute) { insert_native<double>(*this, "test_double", 33.3); }
// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Get a double attribute".
TEST_F(CortexDsrApi, NativeTypesGetADoubleAttribute) { get_native<double>(*this, "test_double", 33.3); }

// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Insert a byte_vector attribute" (the
// second section of that title, which writes a vector<uint64_t>).
TEST_F(CortexDsrApi, NativeTypesInsertAByteVectorAttributeUInt64Vec) {
  insert_native<UInt64Vec>(*this, "test_vec_u64", UInt64Vec{11, 167, 55});
}
// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Get a byte_vector attribute" (the
// vector<uint64_t> one).
TEST_F(CortexDsrApi, NativeTypesGetAByteVectorAttributeUInt64Vec) {
  get_native<UInt64Vec>(*this, "test_vec_u64", UInt64Vec{11, 167, 55});
}

// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Insert an array<float, 2> attribute".
TEST_F(CortexDsrApi, NativeTypesInsertAnArrayFloat2Attribute) { insert_native<Vec2f>(*this, "test_vec2", Vec2f{11.0f, 167.0f}); }
// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Get a array<float, 2> attribute".
TEST_F(CortexDsrApi, NativeTypesGetAArrayFloat2Attribute) { get_native<Vec2f>(*this, "test_vec2", Vec2f{11.0f, 167.0f}); }

// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Insert an array<float, 3> attribute".
TEST_F(CortexDsrApi, NativeTypesInsertAnArrayFloat3Attribute) {
  insert_native<Vec3f>(*this, "test_vec3", Vec3f{11.0f, 167.0f, 0.0f});
}
// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Get a array<float, 3> attribute".
TEST_F(CortexDsrApi, NativeTypesGetAArrayFloat3Attribute) { get_native<Vec3f>(*this, "test_vec3", Vec3f{11.0f, 167.0f, 0.0f}); }

// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Insert an array<float, 4> attribute".
TEST_F(CortexDsrApi, NativeTypesInsertAnArrayFloat4Attribute) {
  insert_native<Vec4f>(*this, "test_vec4", Vec4f{11.0f, 167.0f, 1.0f, 0.0f});
}
// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Get a array<float, 4> attribute".
TEST_F(CortexDsrApi, NativeTypesGetAArrayFloat4Attribute) {
  get_native<Vec4f>(*this, "test_vec4", Vec4f{11.0f, 167.0f, 1.0f, 0.0f});
}

// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Insert an array<float, 6> attribute".
TEST_F(CortexDsrApi, NativeTypesInsertAnArrayFloat6Attribute) {
  insert_native<Vec6f>(*this, "test_vec6", Vec6f{0.0f, 0.0f, 11.0f, 167.0f, 1.0f, 1.0f});
}
// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Get a array<float, 6> attribute".
TEST_F(CortexDsrApi, NativeTypesGetAArrayFloat6Attribute) {
  get_native<Vec6f>(*this, "test_vec6", Vec6f{0.0f, 0.0f, 11.0f, 167.0f, 1.0f, 1.0f});
}

// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Insert an array<float, 6> attribute
// without reference wrapper" (DSR's by-value accessor; Quiver's get<T> always returns a value).
TEST_F(CortexDsrApi, NativeTypesInsertAnArrayFloat6AttributeWithoutReferenceWrapper) {
  insert_native<Vec6f>(*this, "test_vec6_no_reference", Vec6f{0.0f, 0.0f, 11.0f, 167.0f, 1.0f, 0.0f});
}
// CORTEX test_dsr_api.cpp, "Native types in attributes" / "Get a array<float, 6> attribute" (the
// second section of that title, reading test_vec6_no_reference).
TEST_F(CortexDsrApi, NativeTypesGetAArrayFloat6AttributeWithoutReferenceWrapper) {
  get_native<Vec6f>(*this, "test_vec6_no_reference", Vec6f{0.0f, 0.0f, 11.0f, 167.0f, 1.0f, 0.0f});
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
