// Translation of RoboComp CORTEX tests/synchronization/graph_signals.cpp onto Quiver.
//
// CORTEX connects Qt slots to DSRGraph's eight signals and counts them after the event loop ran.
// Quiver calls a subscriber once per commit with a ChangeBatch (graph/changes.h); the DSR
// signals map onto it as docs/dsr-api.md row 28 says:
//   update_node_signal       -> a NodeChange kCreated (or kUpdated)
//   update_node_attr_signal  -> a NodeChange kUpdated, its `attrs` the changed attribute names
//   update_edge_signal       -> an EdgeChange kCreated (or kUpdated)
//   update_edge_attr_signal  -> an EdgeChange kUpdated, its `attrs` the changed attribute names
//   del_node_signal / deleted_node_signal -> a NodeChange kDeleted (carrying name and values)
//   del_edge_signal / deleted_edge_signal -> an EdgeChange kDeleted (carrying its values)
// CORTEX runs each case in CRDT and LWW mode (GENERATE); Quiver has one mode. Callbacks run
// synchronously inside commit(), so no event loop is needed.

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "quiver/graph/graph.h"

namespace quiver::cortex_tests {
namespace {

using graph::ChangeBatch;
using graph::ChangeKind;
using graph::EdgeKey;
using graph::FloatVec;
using graph::Graph;
using graph::NodeId;
using graph::Pose;
using graph::ReplicaId;
using graph::Symbol;
using graph::Value;

// Counts what the subscriber saw, in DSR's signal terms.
struct Signals {
  int batches = 0;
  int node_created = 0, node_updated = 0, node_deleted = 0;
  int edge_created = 0, edge_updated = 0, edge_deleted = 0;
  std::size_t node_updated_attrs = 0, edge_updated_attrs = 0;
  std::vector<graph::NodeChange> deleted_nodes;
  std::vector<graph::EdgeChange> deleted_edges;
  std::vector<graph::EdgeChange> edges;

  void listen(Graph& g) {
    g.subscribe([this](const ChangeBatch& b) {
      ++batches;
      for (const auto& n : b.nodes) {
        if (n.kind == ChangeKind::kCreated) ++node_created;
        if (n.kind == ChangeKind::kUpdated) {
          ++node_updated;
          node_updated_attrs = n.attrs.size();
        }
        if (n.kind == ChangeKind::kDeleted) {
          ++node_deleted;
          deleted_nodes.push_back(n);
        }
      }
      for (const auto& e : b.edges) {
        edges.push_back(e);
        if (e.kind == ChangeKind::kCreated) ++edge_created;
        if (e.kind == ChangeKind::kUpdated) {
          ++edge_updated;
          edge_updated_attrs = e.attrs.size();
        }
        if (e.kind == ChangeKind::kDeleted) {
          ++edge_deleted;
          deleted_edges.push_back(e);
        }
      }
    });
  }
};

// Three attributes of the kinds CORTEX's new_attribute_() picks from (int, string, float vector).
std::vector<std::pair<Symbol, Value>> three_attrs() {
  return {{Symbol("a_int"), Value::int32(12)},
          {Symbol("a_str"), Value("qwerty")},
          {Symbol("a_vec"), Value(FloatVec{1.0f, 2.0f, 3.0f})}};
}

NodeId make_node(Graph& g, const std::string& name, std::vector<std::pair<Symbol, Value>> attrs = {}) {
  auto tx = g.begin();
  auto id = tx.create_node("testtype", name, std::move(attrs));
  EXPECT_TRUE(id.ok());
  EXPECT_TRUE(tx.commit().ok());
  return id.value_or(NodeId{});
}

// CORTEX graph_signals.cpp, "Insert a node without attributes and edges". Class (a): only
// update_node_signal fires.
TEST(CortexGraphSignals, InsertANodeWithoutAttributesAndEdges) {
  Graph g(ReplicaId{1, 1});
  Signals s;
  s.listen(g);
  make_node(g, "n1");
  EXPECT_EQ(s.batches, 1);
  EXPECT_EQ(s.node_created, 1);
  EXPECT_EQ(s.node_updated, 0);
  EXPECT_EQ(s.node_deleted, 0);
  EXPECT_EQ(s.edge_created + s.edge_updated + s.edge_deleted, 0);
}

// CORTEX graph_signals.cpp, "Insert a node with attributes and edges". Class (a): the node's
// creation and one edge signal per edge; no attribute-update signal (the attributes come with the
// creation), no deletion.
TEST(CortexGraphSignals, InsertANodeWithAttributesAndEdges) {
  Graph g(ReplicaId{1, 1});
  NodeId r = make_node(g, "target");
  Signals s;
  s.listen(g);
  const std::vector<std::string> types = {"in", "reachable", "visible"};
  {
    auto tx = g.begin();
    auto id = tx.create_node("testtype", "with_edges", three_attrs());
    ASSERT_TRUE(id.ok());
    for (const auto& t : types) ASSERT_TRUE(tx.insert_edge(*id, r, t).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  EXPECT_EQ(s.node_created, 1);
  EXPECT_EQ(s.edge_created, static_cast<int>(types.size()));
  EXPECT_EQ(s.node_updated, 0);
  EXPECT_EQ(s.edge_updated, 0);
  EXPECT_EQ(s.node_deleted, 0);
  EXPECT_EQ(s.edge_deleted, 0);
}

// CORTEX graph_signals.cpp, "Update a node, add and remove attributes". Class (a): one attribute
// removed and one added in one update: one node-update signal naming both.
TEST(CortexGraphSignals, UpdateANodeAddAndRemoveAttributes) {
  Graph g(ReplicaId{1, 1});
  NodeId id = make_node(g, "n1", three_attrs());
  Signals s;
  s.listen(g);
  {
    auto tx = g.begin();
    auto removed = tx.remove_attr(id, "a_int");
    ASSERT_TRUE(removed.ok());
    ASSERT_TRUE(*removed);
    ASSERT_TRUE(tx.set(id, "a_new", Value("fresh")).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  EXPECT_EQ(s.node_created, 0);
  EXPECT_EQ(s.node_updated, 1);
  EXPECT_EQ(s.node_updated_attrs, 2u);
  EXPECT_EQ(s.edge_created + s.edge_updated + s.edge_deleted, 0);
  EXPECT_EQ(s.node_deleted, 0);
}

// CORTEX graph_signals.cpp, "Insert and edge". Class (a): only update_edge_signal fires.
TEST(CortexGraphSignals, InsertAndEdge) {
  Graph g(ReplicaId{1, 1});
  NodeId r = make_node(g, "n1"), r2 = make_node(g, "n2");
  Signals s;
  s.listen(g);
  {
    auto tx = g.begin();
    ASSERT_TRUE(tx.insert_edge(r, r2, "in").ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  EXPECT_EQ(s.edge_created, 1);
  EXPECT_EQ(s.edge_updated, 0);
  EXPECT_EQ(s.edge_deleted, 0);
  EXPECT_EQ(s.node_created + s.node_updated + s.node_deleted, 0);
}

// CORTEX graph_signals.cpp, "Update an edge, add and remove attributes". Class (a): the edge is
// inserted again with one attribute dropped and one added (DSR's insert_or_assign_edge): one
// edge-update signal naming both changed attributes, nothing on nodes.
TEST(CortexGraphSignals, UpdateAnEdgeAddAndRemoveAttributes) {
  Graph g(ReplicaId{1, 1});
  NodeId r = make_node(g, "n1"), r2 = make_node(g, "n2");
  {
    auto tx = g.begin();
    ASSERT_TRUE(tx.insert_edge(r, r2, Symbol("in"), three_attrs()).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  Signals s;
  s.listen(g);
  {
    auto attrs = three_attrs();
    attrs.erase(attrs.begin());  // drop a_int
    attrs.emplace_back(Symbol("a_new"), Value("fresh"));
    auto tx = g.begin();
    ASSERT_TRUE(tx.insert_edge(r, r2, Symbol("in"), attrs).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  EXPECT_EQ(s.node_created + s.node_updated + s.node_deleted, 0);
  EXPECT_EQ(s.node_updated_attrs, 0u);
  EXPECT_EQ(s.edge_updated, 1);
  EXPECT_EQ(s.edge_updated_attrs, 2u);
  EXPECT_EQ(s.edge_created, 0);
  EXPECT_EQ(s.edge_deleted, 0);
}

// CORTEX graph_signals.cpp, "delete a node". Class (a): deleting a node with an edge out (with
// attributes) and an edge in: one node deletion, carrying the node (name), and two edge
// deletions, carrying the edge (its attribute values); no update signals.
TEST(CortexGraphSignals, DeleteANode) {
  Graph g(ReplicaId{1, 1});
  NodeId r = make_node(g, "n1"), r2 = make_node(g, "n2");
  {
    auto tx = g.begin();
    ASSERT_TRUE(tx.insert_edge(r, r2, Symbol("in"), three_attrs()).ok());
    ASSERT_TRUE(tx.insert_edge(r2, r, "visible").ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  Signals s;
  s.listen(g);
  {
    auto tx = g.begin();
    ASSERT_TRUE(tx.delete_node(r).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  EXPECT_EQ(s.node_created + s.node_updated, 0);
  EXPECT_EQ(s.edge_created + s.edge_updated, 0);
  EXPECT_EQ(s.node_updated_attrs, 0u);
  EXPECT_EQ(s.edge_updated_attrs, 0u);
  ASSERT_EQ(s.node_deleted, 1);
  EXPECT_EQ(s.deleted_nodes[0].id, r);
  EXPECT_EQ(s.deleted_nodes[0].name, "n1");
  EXPECT_EQ(s.deleted_nodes[0].type, Symbol("testtype"));
  ASSERT_EQ(s.edge_deleted, 2);
  std::size_t with_values = 0;
  for (const auto& e : s.deleted_edges)
    if (e.key == EdgeKey{r, r2, Symbol("in")}) with_values = e.values.size();
  EXPECT_EQ(with_values, 3u);
}

// CORTEX graph_signals.cpp, "delete an edge". Class (a): one edge deletion (carrying its
// attributes), nothing else.
TEST(CortexGraphSignals, DeleteAnEdge) {
  Graph g(ReplicaId{1, 1});
  NodeId r = make_node(g, "n1"), r2 = make_node(g, "n2");
  {
    auto tx = g.begin();
    ASSERT_TRUE(tx.insert_edge(r, r2, Symbol("in"), three_attrs()).ok());
    ASSERT_TRUE(tx.insert_edge(r2, r, "visible").ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  Signals s;
  s.listen(g);
  {
    auto tx = g.begin();
    ASSERT_TRUE(tx.delete_edge(r, r2, "in").ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  EXPECT_EQ(s.node_created + s.node_updated + s.node_deleted, 0);
  EXPECT_EQ(s.edge_created + s.edge_updated, 0);
  ASSERT_EQ(s.edge_deleted, 1);
  EXPECT_EQ(s.deleted_edges[0].key, (EdgeKey{r, r2, Symbol("in")}));
  EXPECT_EQ(s.deleted_edges[0].values.size(), 3u);
  EXPECT_TRUE(g.has_edge(r2, r, "visible"));
}

// CORTEX graph_signals.cpp, "RT api signals". Class (b): in DSR, insert_or_assign_edge_RT writes
// the child's `parent` and `level` attributes (a node signal and a node-attribute signal naming
// 2) and the edge's rt_translation and rt_rotation_euler_xyz (an edge signal and an
// edge-attribute signal naming 2). A Quiver RT edge holds a pose, and parent and level are
// derived from the tree (docs/dsr-api.md rows 21-22): set_rt gives one RT edge creation and no
// node change; a new pose for the same parent gives one RT edge update naming "pose".
TEST(CortexGraphSignals, RtApiSignals) {
  Graph g(ReplicaId{1, 1});
  NodeId r = make_node(g, "n1", {{Symbol("level"), Value::int32(0)}});
  NodeId r2 = make_node(g, "n2");
  Signals s;
  s.listen(g);
  Pose p;
  p.translation = {0.0, 0.2, 0.5};
  {
    auto tx = g.begin();
    ASSERT_TRUE(tx.set_rt(r, r2, p, 1).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  EXPECT_EQ(s.node_created + s.node_updated + s.node_deleted, 0);
  ASSERT_EQ(s.edge_created, 1);
  EXPECT_EQ(s.edges[0].key, (EdgeKey{r, r2, graph::symbols::rt()}));
  EXPECT_EQ(s.edge_updated + s.edge_deleted, 0);
  EXPECT_EQ(g.rt_parent(r2), r);

  p.translation = {0.0, 0.3, 0.5};
  {
    auto tx = g.begin();
    ASSERT_TRUE(tx.set_rt(r, r2, p, 2).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  EXPECT_EQ(s.node_created + s.node_updated + s.node_deleted, 0);
  ASSERT_EQ(s.edge_updated, 1);
  ASSERT_EQ(s.edges.back().attrs.size(), 1u);
  EXPECT_EQ(s.edges.back().attrs[0], Symbol("pose"));
}

}  // namespace
}  // namespace quiver::cortex_tests
