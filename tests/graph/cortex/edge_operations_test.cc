// Translation onto Quiver of RoboComp CORTEX's DSR tests, file tests/graph/edge_operations.cpp
// (robocomp/cortex). Each TEST names the CORTEX TEST_CASE / SECTION it keeps the intent of.
//
// The graph is seeded from data/empty_world.json, the Quiver-format copy of CORTEX's
// make_empty_config_file() (tests/utils.h): one node "root". DSR's Node::create<testtype_node_type>()
// names a node itself; Quiver's create_node() takes the name. DSR's ids are uint64 from an id
// generator; Quiver's are creation dots, so an absent id is a dot of a replica that never wrote.

#include <gtest/gtest.h>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "cortex_graph_fixture.h"

namespace quiver::cortex_tests {
namespace {


class CortexGraphEdgeOperations : public CortexWorldTest {
 protected:
  CortexGraphEdgeOperations() : CortexWorldTest("empty_world.json", ReplicaId{0xC2, 1}) {}
  // Two testtype nodes, each inserted on its own (DSR's insert_node per node).
  void insert_two_nodes() {
    for (auto [name, out] : {std::pair{"testtype_a", &id1}, std::pair{"testtype_b", &id2}}) {
      auto id = try_insert_node("testtype", name);
      ASSERT_TRUE(id.ok()) << id.error().to_string();
      *out = *id;
    }
  }
  template <class... Args>
  Status delete_edge(Args&&... args) {
    auto tx = g.begin();
    if (Status s = tx.delete_edge(std::forward<Args>(args)...); !s.ok()) return s;
    return commit(tx);
  }

  NodeId id1, id2;
};

// ---- TEST_CASE "Graph edge operations" ----

// CORTEX edge_operations.cpp, "Graph edge operations" / "Get an edge that does not exists by id". (a)
TEST_F(CortexGraphEdgeOperations, GetAnEdgeThatDoesNotExistsById) {
  EXPECT_FALSE(g.has_edge(absent_id(17), absent_id(18), "zT4kQ9mXc2"));
  EXPECT_FALSE(g.has_edge(absent_id(17), absent_id(18), Symbol("in")));
}

// CORTEX edge_operations.cpp, "Graph edge operations" / "Get an edge that does not exists by name". (a)
TEST_F(CortexGraphEdgeOperations, GetAnEdgeThatDoesNotExistsByName) {
  EXPECT_FALSE(g.find_edge("Hq2wE3rT4y", "Uu5iO6pA7s", "Dd8fG9hJ0k").has_value());
  EXPECT_FALSE(g.find_edge("root", "root", "in").has_value());
}

// CORTEX edge_operations.cpp, "Graph edge operations" / "Insert a new edge and get it by name and id". (a)
TEST_F(CortexGraphEdgeOperations, InsertANewEdgeAndGetItByNameAndId) {
  insert_two_nodes();
  ASSERT_TRUE(insert_edge(id1, id2, "in").ok());
  EXPECT_TRUE(g.has_edge(id1, id2, "in"));

  auto name_ori = g.find_name(id1);
  ASSERT_TRUE(name_ori.has_value());
  auto name_dst = g.find_name(id2);
  ASSERT_TRUE(name_dst.has_value());

  auto e_name = g.find_edge(*name_ori, *name_dst, "in");
  ASSERT_TRUE(e_name.has_value());
  EXPECT_EQ(*e_name, (EdgeKey{id1, id2, Symbol("in")}));

  // DSR's get_edge(node, to_name, type): the origin as a node, the destination by name.
  auto new_n = g.find_node(*name_ori);
  ASSERT_TRUE(new_n.has_value());
  auto to = g.find_node(*name_dst);
  ASSERT_TRUE(to.has_value());
  EXPECT_TRUE(g.has_edge(*new_n, *to, "in"));
}

// CORTEX edge_operations.cpp, "Graph edge operations" / "Update existing edge". (a)
TEST_F(CortexGraphEdgeOperations, UpdateExistingEdge) {
  insert_two_nodes();
  ASSERT_TRUE(insert_edge(id1, id2, "in").ok());
  auto edges = g.edges_of_type("in");
  ASSERT_GT(edges.size(), 0u);
  const EdgeKey e = edges.at(0);
  // add_attrib_local<name_att>(e, ...) then insert_or_assign_edge(e).
  EXPECT_TRUE(insert_edge(e.from, e.to, e.type.str(), {{Symbol("name"), Value("r9Tg2Lk0Pq")}}).ok());
  EXPECT_EQ(g.get<std::string>(e, "name").value(), "r9Tg2Lk0Pq");
}

// CORTEX edge_operations.cpp, "Graph edge operations" / "Delete existing edge by id and name". (a)
TEST_F(CortexGraphEdgeOperations, DeleteExistingEdgeByIdAndName) {
  insert_two_nodes();
  ASSERT_TRUE(insert_edge(id1, id2, "in").ok());
  auto edges = g.edges_of_type("in");
  ASSERT_EQ(edges.size(), 1u);
  const EdgeKey e = edges.at(0);
  EXPECT_TRUE(delete_edge(e.from, e.to, std::string_view("in")).ok());
  EXPECT_FALSE(g.has_edge(e.from, e.to, "in"));

  // Reinsert it.
  EXPECT_TRUE(insert_edge(e.from, e.to, "in").ok());
  auto name_ori = g.find_name(e.from);
  ASSERT_TRUE(name_ori.has_value());
  auto name_dst = g.find_name(e.to);
  ASSERT_TRUE(name_dst.has_value());
  EXPECT_TRUE(delete_edge(std::string_view(*name_ori), std::string_view(*name_dst), std::string_view("in")).ok());
  EXPECT_FALSE(g.find_edge(*name_ori, *name_dst, "in").has_value());
}

// CORTEX edge_operations.cpp, "Graph edge operations" / "Delete an edge that does not exists". (a)
TEST_F(CortexGraphEdgeOperations, DeleteAnEdgeThatDoesNotExists) {
  EXPECT_EQ(g.edges_of_type("in").size(), 0u);
  Status s = delete_edge(absent_id(31), absent_id(32), std::string_view("in"));
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().code, ErrorCode::kNotFound);
}

// CORTEX edge_operations.cpp, "Graph edge operations" /
// "Deleting one edge type between a pair leaves other types intact". (a)
TEST_F(CortexGraphEdgeOperations, DeletingOneEdgeTypeBetweenAPairLeavesOtherTypesIntact) {
  insert_two_nodes();
  ASSERT_TRUE(insert_edge(id1, id2, "in").ok());
  ASSERT_TRUE(insert_edge(id1, id2, "knows").ok());
  ASSERT_TRUE(delete_edge(id1, id2, std::string_view("in")).ok());
  EXPECT_FALSE(g.has_edge(id1, id2, "in"));
  EXPECT_TRUE(g.has_edge(id1, id2, "knows"));
  EXPECT_EQ(g.edges_of_type("knows").size(), 1u);
}

// ---- TEST_CASE "Edge creation" ----

// CORTEX edge_operations.cpp, "Edge creation" / "Runtime set of an edge type". (a) DSR checks an
// edge type against its compiled registry and throws for "invalidtype". Quiver's registry is the
// schema every agent loads (docs/schema.md): with one declaring this file's types ("testtype"
// nodes, "in" edges), an "in" edge is accepted and an "invalidtype" edge is refused at commit
// (kPermissionDenied), leaving the graph unchanged.
TEST(CortexEdgeCreation, RuntimeSetOfAnEdgeType) {
  Graph g{ReplicaId{0xC3, 1}};
  auto parsed = agents::schema::Schema::parse(
      R"({"quiver_schema": 1, "node_types": {"testtype": {}}, "edge_types": {"in": {}}})", "cortex_registry");
  ASSERT_TRUE(parsed.ok()) << parsed.error().to_string();
  auto registry = std::make_shared<const agents::schema::Schema>(*parsed);
  agents::schema::SchemaAdmission adm(registry, nullptr);
  g.set_permission_check(adm.commit_check(g.replica().agent));
  g.set_type_change_check(adm.type_change_check());

  NodeId a, b;
  {
    auto tx = g.begin();
    a = tx.create_node("testtype", "a").value();
    b = tx.create_node("testtype", "b").value();
    ASSERT_TRUE(tx.commit().ok());
  }
  {
    auto tx = g.begin();
    ASSERT_TRUE(tx.insert_edge(a, b, "in").ok());
    auto c = tx.commit();
    EXPECT_TRUE(c.ok()) << c.error().to_string();
  }
  EXPECT_TRUE(g.has_edge(a, b, "in"));
  {
    auto tx = g.begin();
    ASSERT_TRUE(tx.insert_edge(a, b, "invalidtype").ok());
    auto c = tx.commit();
    ASSERT_FALSE(c.ok());
    EXPECT_EQ(c.error().code, ErrorCode::kPermissionDenied);
  }
  EXPECT_FALSE(g.has_edge(a, b, "invalidtype"));
}

}  // namespace
}  // namespace quiver::cortex_tests
