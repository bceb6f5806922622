// Translation onto Quiver of RoboComp CORTEX's DSR tests, file tests/graph/node_operations.cpp
// (robocomp/cortex). Each TEST names the CORTEX TEST_CASE / SECTION it keeps the intent of.
//
// CORTEX runs its cases under SyncMode::CRDT and SyncMode::LWW; Quiver has one merge semantics.
// The graph is seeded from data/empty_world.json (CORTEX's make_empty_config_file(): one node
// "root"). DSR's ids come from an id generator (and may be chosen with insert_node_with_id);
// Quiver's are creation dots: an absent id is a dot of a replica that never wrote. The sections of
// TEST_CASE "Insert node with specific id" that choose ids are not translated (see the report).

#include <gtest/gtest.h>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "cortex_graph_fixture.h"

namespace quiver::cortex_tests {
namespace {


// DSR's compiled type registry as Quiver's schema (docs/schema.md): the node types of this file
// ("root" of the world file, "testtype") and its edge type "in". Installed as DSR has it, on
// every commit of `g`: a node or edge of an undeclared type is refused with kPermissionDenied.
void install_registry(Graph& g) {
  install_schema(g, R"({"quiver_schema": 1, "node_types": {"root": {}, "testtype": {}}, "edge_types": {"in": {}}})");
}

class CortexGraphNodeOperations : public CortexWorldTest {
 protected:
  CortexGraphNodeOperations() : CortexWorldTest("empty_world.json", ReplicaId{0xC5, 1}) {}
  // DSR's insert_node(Node::create<testtype_node_type>(name)).
  Result<NodeId> insert_testtype(std::string_view name) { return try_insert_node("testtype", name); }
};

// ---- TEST_CASE "Graph node operations" ----

// CORTEX node_operations.cpp, "Graph node operations" / "Try to get a node that does not exists by a id". (a)
TEST_F(CortexGraphNodeOperations, TryToGetANodeThatDoesNotExistsByAnId) {
  EXPECT_FALSE(g.has_node(absent_id(1234)));
  EXPECT_FALSE(g.find_name(absent_id(1234)).has_value());
}

// CORTEX node_operations.cpp, "Graph node operations" / "Try to get a node that does not exists by a name". (a)
TEST_F(CortexGraphNodeOperations, TryToGetANodeThatDoesNotExistsByAName) {
  EXPECT_FALSE(g.find_node("Wm3nB7vC1x").has_value());
}

// CORTEX node_operations.cpp, "Graph node operations" / "Insert a new node and get it by id and name". (a)
TEST_F(CortexGraphNodeOperations, InsertANewNodeAndGetItByIdAndName) {
  auto r = insert_testtype("Pz4oI9uY2t");
  ASSERT_TRUE(r.ok()) << r.error().to_string();
  EXPECT_TRUE(g.has_node(*r));
  auto by_name = g.find_node("Pz4oI9uY2t");
  ASSERT_TRUE(by_name.has_value());
  EXPECT_EQ(*by_name, *r);
}

// CORTEX node_operations.cpp, "Graph node operations" / "Create a node with an invalid type". (a)
// DSR checks node types against its compiled registry and throws for an unregistered one (a
// random 100-character type). Quiver's registry is the schema (install_registry()): a node of a
// type it does not declare is refused at commit with kPermissionDenied, and is not created.
TEST_F(CortexGraphNodeOperations, CreateANodeWithAnInvalidType) {
  ASSERT_NO_FATAL_FAILURE(install_registry(g));
  const std::string random_type =
      "q8Zr2Lk5Vb0Nx7Cm4Hs1Jd6Fg3Tw9Ye2Ua5Oi8Pl1Kj4Mh7Bn0Vc3Xz6Ws9Ed2Rf5Tg8Yh1Uj4Ik7Ol0Pa3Sd6Fg9Hj2Kl5Zx8Cv";
  ASSERT_EQ(random_type.size(), 100u);
  auto tx = g.begin();
  ASSERT_TRUE(tx.create_node(random_type, "random_typed").ok());
  auto c = tx.commit();
  ASSERT_FALSE(c.ok());
  EXPECT_EQ(c.error().code, ErrorCode::kPermissionDenied);
  EXPECT_FALSE(g.find_node("random_typed").has_value());
}

// CORTEX node_operations.cpp, "Graph node operations" / "Update existing node". (a)
TEST_F(CortexGraphNodeOperations, UpdateExistingNode) {
  auto r = insert_testtype("Ae4sR7dT0f");
  ASSERT_TRUE(r.ok());
  auto n_id = g.find_node("Ae4sR7dT0f");
  ASSERT_TRUE(n_id.has_value());
  {
    auto tx = g.begin();
    ASSERT_TRUE(tx.set(*n_id, "level", Value::int32(1)).ok());
    EXPECT_TRUE(commit(tx).ok());
  }
  {
    auto tx = g.begin();
    auto removed = tx.remove_attr(*n_id, "level");
    ASSERT_TRUE(removed.ok());
    EXPECT_TRUE(*removed);
    ASSERT_TRUE(commit(tx).ok());
  }
  EXPECT_EQ(g.attr(*n_id, "level"), nullptr);
  auto tx = g.begin();
  auto again = tx.remove_attr(*n_id, "level");
  ASSERT_TRUE(again.ok());
  EXPECT_FALSE(*again);
}

// CORTEX node_operations.cpp, "Graph node operations" / "Update existing node repeatedly". (a)
TEST_F(CortexGraphNodeOperations, UpdateExistingNodeRepeatedly) {
  auto r = insert_testtype("Gh5jK8lZ1x");
  ASSERT_TRUE(r.ok());
  for (std::int32_t value : {1, 2, 3}) {
    ASSERT_TRUE(g.has_node(*r));
    auto tx = g.begin();
    ASSERT_TRUE(tx.set(*r, "level", Value::int32(value)).ok());
    EXPECT_TRUE(commit(tx).ok());
  }
  ASSERT_TRUE(g.has_node(*r));
  EXPECT_EQ(g.get<std::int32_t>(*r, "level").value(), 3);
}

// CORTEX node_operations.cpp, "Graph node operations" / "Can't update an existent node with
// different id". (a) DSR's update_node of a node whose id is not in the graph throws; Quiver's
// write to an id no node has is refused with kNotFound.
TEST_F(CortexGraphNodeOperations, CantUpdateAnExistentNodeWithDifferentId) {
  ASSERT_TRUE(insert_testtype("Cv6bN9mQ2w").ok());
  auto tx = g.begin();
  Status s = tx.set(absent_id(777), "level", Value::int32(1));
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().code, ErrorCode::kNotFound);
}

// CORTEX node_operations.cpp, "Graph node operations" / "Can't update an existent node with
// different name". (b) DSR's update_node refuses (throws) a node copy whose name was changed.
// Quiver has no Node copy and no rename: a node's name is fixed at creation, and "name" is an
// ordinary attribute name, so writing it leaves the node's name (and its lookup) unchanged.
TEST_F(CortexGraphNodeOperations, CantUpdateAnExistentNodeWithDifferentName) {
  auto r = insert_testtype("Er7tY0uI3o");
  ASSERT_TRUE(r.ok());
  auto tx = g.begin();
  ASSERT_TRUE(tx.set(*r, "name", Value("Lp1aS4dF7g")).ok());
  ASSERT_TRUE(commit(tx).ok());
  EXPECT_EQ(g.name_of(*r), "Er7tY0uI3o");
  EXPECT_EQ(g.find_node("Er7tY0uI3o"), std::optional<NodeId>(*r));
  EXPECT_FALSE(g.find_node("Lp1aS4dF7g").has_value());
}

// CORTEX node_operations.cpp, "Graph node operations" / "Delete existing node by id". (a)
TEST_F(CortexGraphNodeOperations, DeleteExistingNodeById) {
  ASSERT_TRUE(insert_testtype("Hj2kL5zX8c").ok());
  auto n = g.find_node("Hj2kL5zX8c");
  ASSERT_TRUE(n.has_value());
  auto tx = g.begin();
  EXPECT_TRUE(tx.delete_node(*n).ok());
  EXPECT_TRUE(commit(tx).ok());
  EXPECT_FALSE(g.find_node("Hj2kL5zX8c").has_value());
}

// CORTEX node_operations.cpp, "Graph node operations" / "Delete existing node by name". (a)
// Quiver deletes by id; the name is resolved with find_node() (docs/dsr-api.md row 27).
TEST_F(CortexGraphNodeOperations, DeleteExistingNodeByName) {
  ASSERT_TRUE(insert_testtype("Vb3nM6qW9e").ok());
  ASSERT_TRUE(g.find_node("Vb3nM6qW9e").has_value());
  auto tx = g.begin();
  auto by_name = g.find_node("Vb3nM6qW9e");
  ASSERT_TRUE(by_name.has_value());
  EXPECT_TRUE(tx.delete_node(*by_name).ok());
  EXPECT_TRUE(commit(tx).ok());
  EXPECT_FALSE(g.find_node("Vb3nM6qW9e").has_value());
}

// CORTEX node_operations.cpp, "Graph node operations" / "Delete a node that does not exists by id". (a)
TEST_F(CortexGraphNodeOperations, DeleteANodeThatDoesNotExistsById) {
  auto tx = g.begin();
  Status s = tx.delete_node(absent_id(31337));
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().code, ErrorCode::kNotFound);
}

// CORTEX node_operations.cpp, "Graph node operations" / "Deleting a node removes incoming edges
// from other nodes". (a)
TEST_F(CortexGraphNodeOperations, DeletingANodeRemovesIncomingEdgesFromOtherNodes) {
  auto id1 = insert_testtype("testtype_1");
  auto id2 = insert_testtype("testtype_2");
  ASSERT_TRUE(id1.ok() && id2.ok());
  {
    auto tx = g.begin();
    ASSERT_TRUE(tx.insert_edge(*id1, *id2, "in").ok());
    ASSERT_TRUE(commit(tx).ok());
  }
  ASSERT_TRUE(g.has_edge(*id1, *id2, "in"));
  {
    auto tx = g.begin();
    ASSERT_TRUE(tx.delete_node(*id2).ok());
    ASSERT_TRUE(commit(tx).ok());
  }
  EXPECT_FALSE(g.has_edge(*id1, *id2, "in"));
  EXPECT_TRUE(g.edges_from(*id1).empty());
  EXPECT_TRUE(g.has_node(*id1));
}

// CORTEX node_operations.cpp, "Graph node operations" / "Create a node with an user defined name".
// (a) DSR's insert_node ignores the id set on the Node (1550) and keeps the name; Quiver's
// create_node takes the name and hands out the id.
TEST_F(CortexGraphNodeOperations, CreateANodeWithAnUserDefinedName) {
  auto tx = g.begin();
  auto r = tx.create_node("testtype", "Nm8bV5cX2z");
  ASSERT_TRUE(r.ok());
  ASSERT_TRUE(commit(tx).ok());
  EXPECT_EQ(g.find_node("Nm8bV5cX2z"), std::optional<NodeId>(*r));
}

// ---- TEST_CASE "Insert node with specific id" ----
// "Insert a node with a specific id" and "Insert a node with a duplicate id fails": not
// translatable (Quiver's ids are creation dots; no call chooses one).

// CORTEX node_operations.cpp, "Insert node with specific id" / "Insert a node with empty name
// generates a name". (b) DSR makes up a name for a node inserted without one; Quiver refuses an
// empty name (kInvalidArgument): names are the user's, never generated locally.
TEST_F(CortexGraphNodeOperations, InsertANodeWithEmptyNameGeneratesAName) {
  auto tx = g.begin();
  auto r = tx.create_node("testtype", "");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, ErrorCode::kInvalidArgument);
  EXPECT_TRUE(tx.empty());
}

// CORTEX node_operations.cpp, "Insert node with specific id" / "Insert a node with a duplicate name
// generates a new name". (b) DSR renames the second node. Quiver refuses a local create with a
// taken name (kAlreadyExists); namesakes created concurrently on two replicas are both kept, and
// all but the earliest (Lamport order) read as "name~<id>", a new name that find_node() resolves.
TEST_F(CortexGraphNodeOperations, InsertANodeWithADuplicateNameGeneratesANewName) {
  const std::string shared_name = "Sh4rEdNaMe";
  auto r1 = insert_testtype(shared_name);
  ASSERT_TRUE(r1.ok());
  auto local = insert_testtype(shared_name);
  ASSERT_FALSE(local.ok());
  EXPECT_EQ(local.error().code, ErrorCode::kAlreadyExists);

  // A second replica creates a namesake concurrently; the two merge.
  Graph other{ReplicaId{0xC6, 1}};
  NodeId r2;
  {
    auto tx = other.begin();
    auto id = tx.create_node("testtype", shared_name);
    ASSERT_TRUE(id.ok());
    ASSERT_TRUE(tx.commit().ok());
    r2 = *id;
  }
  g.merge(other.state());
  other.merge(g.state());
  ASSERT_TRUE(g.has_node(*r1));
  ASSERT_TRUE(g.has_node(r2));
  EXPECT_EQ(g.namesakes(shared_name).size(), 2u);
  const NodeId holder = g.find_node(shared_name).value();
  const NodeId renamed = holder == *r1 ? r2 : *r1;
  EXPECT_NE(g.name_of(renamed), shared_name);
  EXPECT_EQ(g.name_of(renamed), shared_name + "~" + renamed.to_string());
  EXPECT_EQ(g.find_node(g.name_of(renamed)), std::optional<NodeId>(renamed));
  // Both replicas agree on who holds the name.
  EXPECT_EQ(other.find_node(shared_name), std::optional<NodeId>(holder));
}

// ---- TEST_CASE "Node creation" ----

// CORTEX node_operations.cpp, "Node creation" / "Runtime set of a node type". (a) DSR accepts
// the registered "testtype" and throws for "invalidtype". With the registry as Quiver's schema
// (install_registry()), a "testtype" node is created and an "invalidtype" one is refused at
// commit (kPermissionDenied).
TEST(CortexNodeCreation, RuntimeSetOfANodeType) {
  Graph g{ReplicaId{0xC7, 1}};
  ASSERT_NO_FATAL_FAILURE(install_registry(g));
  {
    auto tx = g.begin();
    auto a = tx.create_node("testtype", "a");
    ASSERT_TRUE(a.ok());
    auto c = tx.commit();
    ASSERT_TRUE(c.ok()) << c.error().to_string();
    EXPECT_EQ(g.type_of(*a).str(), "testtype");
  }
  {
    auto tx = g.begin();
    ASSERT_TRUE(tx.create_node("invalidtype", "b").ok());
    auto c = tx.commit();
    ASSERT_FALSE(c.ok());
    EXPECT_EQ(c.error().code, ErrorCode::kPermissionDenied);
  }
  EXPECT_FALSE(g.find_node("b").has_value());
}

}  // namespace
}  // namespace quiver::cortex_tests
