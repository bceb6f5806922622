// Translation of RoboComp CORTEX tests/synchronization/type_translation.cpp onto Quiver.
//
// CORTEX converts its user Node/Edge into CRDT types, writes them into a multi-value register,
// and round-trips the register through Fast-CDR, checking that id, name, type, agent, attributes
// and edges survive. Quiver has no Node/Edge value objects (reads go to the graph, docs/dsr-api.md
// "Reads are direct"); the CRDT form of a change is the GraphDelta a commit publishes, its
// serialization is the delta codec (graph/codec.h), and the protocol's messages travel as CDR
// samples (agents/transport/wire/cdr_sample.h). The round trip is therefore: commit on one graph,
// encode the delta, decode it, join it into a fresh graph, and compare.
//
// CORTEX GENERATEs the node with and without 4 attributes and with and without 3 edges; each
// test below loops over the four combinations.

#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <variant>
#include <vector>

#include "quiver/agents/replica/replication/messages.h"
#include "quiver/agents/transport/wire/cdr_sample.h"
#include "quiver/graph/codec.h"
#include "quiver/graph/graph.h"

namespace quiver::cortex_tests {
namespace {

using agents::DeltaMsg;
using agents::PullMsg;
using agents::Range;
using agents::Sample;
using agents::StateMsg;
using graph::EdgeKey;
using graph::FloatVec;
using graph::Graph;
using graph::GraphDelta;
using graph::NodeId;
using graph::ReplicaId;
using graph::Symbol;
using graph::Value;

constexpr std::uint64_t kAgent = 4242;

std::vector<std::pair<Symbol, Value>> four_attrs() {
  return {{Symbol("attr_int"), Value::int32(12)},
          {Symbol("attr_str"), Value("xK3pQ9")},
          {Symbol("attr_vec"), Value(FloatVec{1.0f, 2.0f, 3.0f})},
          {Symbol("attr_str2"), Value("mN7tR2")}};
}

// A graph holding the targets of the edges; the node under test is created in a later commit
// whose delta is returned.
struct NodeCase {
  Graph g{ReplicaId{kAgent, 1}};
  std::vector<GraphDelta> out;
  NodeId id;
  std::vector<NodeId> targets;
  std::size_t n_attrs = 0, n_edges = 0;

  NodeCase(bool with_attrs, bool with_edges) {
    g.set_delta_sink([this](const GraphDelta& d) { out.push_back(d); });
    auto tx = g.begin();
    for (const char* t : {"t_in", "t_reachable", "t_visible"}) targets.push_back(tx.create_node("thing", t).value());
    EXPECT_TRUE(tx.commit().ok());
    auto attrs = with_attrs ? four_attrs() : std::vector<std::pair<Symbol, Value>>{};
    n_attrs = attrs.size();
    auto tx2 = g.begin();
    id = tx2.create_node("robot", "node_under_test", attrs).value();
    if (with_edges) {
      const char* types[] = {"in", "reachable", "visible"};
      for (int i = 0; i < 3; ++i) EXPECT_TRUE(tx2.insert_edge(id, targets[i], Symbol(types[i]), attrs).ok());
      n_edges = 3;
    }
    EXPECT_TRUE(tx2.commit().ok());
  }
};

// Checks that a node round-tripped through the codec arrives whole in a fresh graph.
void check_node_round_trip(const NodeCase& c, const GraphDelta& decoded) {
  // The decoded CRDT form names the node with its id, type and name.
  const GraphDelta::NodeOp* op = nullptr;
  for (const auto& n : decoded.nodes)
    if (n.id == c.id) op = &n;
  ASSERT_NE(op, nullptr);
  EXPECT_TRUE(op->has_header);
  EXPECT_EQ(op->name, "node_under_test");
  EXPECT_EQ(op->type, Symbol("robot"));
  EXPECT_EQ(decoded.origin, c.g.replica());
  // Joined into a replica that has the first commit, it yields the same node.
  Graph fresh(ReplicaId{kAgent + 1, 1});
  fresh.merge(c.out.front());  // the edges' targets
  fresh.merge(decoded);
  ASSERT_TRUE(fresh.has_node(c.id));
  EXPECT_EQ(fresh.attr_names(c.id).size(), c.n_attrs);
  EXPECT_EQ(fresh.edges_from(c.id).size(), c.n_edges);
  EXPECT_EQ(fresh.name_of(c.id), "node_under_test");
  EXPECT_EQ(fresh.type_of(c.id), Symbol("robot"));
  EXPECT_EQ(c.id.dot.replica.agent, kAgent);  // the agent that made it
  for (const auto& [name, value] : (c.n_attrs ? four_attrs() : std::vector<std::pair<Symbol, Value>>{})) {
    const Value* v = fresh.attr(c.id, name);
    ASSERT_NE(v, nullptr);
    EXPECT_EQ(*v, value);
  }
  EXPECT_EQ(fresh.digest(), c.g.digest());
}

// CORTEX type_translation.cpp, "NODE: from DSR representation to CRDT and back via
// serialization" / SECTION "User Node representation". Class (b): there is no user Node object
// to fill; a node is created in a graph, and its edges (fano), attributes, id (the creating
// agent's dot), name and type are read back from the graph.
TEST(CortexTypeTranslation, NodeUserNodeRepresentation) {
  for (bool with_attrs : {false, true})
    for (bool with_edges : {false, true}) {
      SCOPED_TRACE(testing::Message() << "attrs " << with_attrs << " edges " << with_edges);
      NodeCase c(with_attrs, with_edges);
      EXPECT_EQ(c.g.edges_from(c.id).size(), c.n_edges);
      EXPECT_EQ(c.g.attr_names(c.id).size(), c.n_attrs);
      EXPECT_EQ(c.g.name_of(c.id), "node_under_test");
      EXPECT_EQ(c.g.type_of(c.id), Symbol("robot"));
      EXPECT_EQ(c.id.dot.replica, c.g.replica());
      if (with_edges)
        for (const EdgeKey& k : c.g.edges_from(c.id)) EXPECT_EQ(c.g.edge_attr_names(k).size(), c.n_attrs);
    }
}

// CORTEX type_translation.cpp, "NODE: ..." / SECTION "Copy node — CRDT round-trip". Class (a):
// the node's CRDT form (the commit's delta, kept as a copy) survives serialization with its id,
// name, type, agent, attributes and edges.
TEST(CortexTypeTranslation, NodeCopyNodeCrdtRoundTrip) {
  for (bool with_attrs : {false, true})
    for (bool with_edges : {false, true}) {
      SCOPED_TRACE(testing::Message() << "attrs " << with_attrs << " edges " << with_edges);
      NodeCase c(with_attrs, with_edges);
      const GraphDelta& delta = c.out.back();
      std::vector<std::uint8_t> bytes = graph::encode(delta);
      auto decoded = graph::decode(bytes);
      ASSERT_TRUE(decoded.ok()) << decoded.error().to_string();
      EXPECT_EQ(graph::encode(*decoded), bytes);  // what was read encodes to the same bytes
      check_node_round_trip(c, *decoded);
    }
}

// CORTEX type_translation.cpp, "NODE: ..." / SECTION "Move node — CRDT round-trip". Class (a):
// the same with the delta and its bytes moved rather than copied.
TEST(CortexTypeTranslation, NodeMoveNodeCrdtRoundTrip) {
  for (bool with_attrs : {false, true})
    for (bool with_edges : {false, true}) {
      SCOPED_TRACE(testing::Message() << "attrs " << with_attrs << " edges " << with_edges);
      NodeCase c(with_attrs, with_edges);
      GraphDelta moved = std::move(c.out.back());
      std::vector<std::uint8_t> bytes = graph::encode(moved);
      std::vector<std::uint8_t> taken = std::move(bytes);
      auto decoded = graph::decode(taken);
      ASSERT_TRUE(decoded.ok()) << decoded.error().to_string();
      GraphDelta result = std::move(*decoded);
      check_node_round_trip(c, result);
    }
}

Sample cdr_round_trip(const Sample& s) {
  auto cdr = agents::encode_cdr_sample(s);
  auto back = agents::decode_cdr_sample(cdr.topic, cdr.bytes);
  EXPECT_TRUE(back.ok()) << back.error().to_string();
  return back.ok() ? *back : Sample{};
}

// CORTEX type_translation.cpp, "Wire metadata round-trip preserves sync mode" / SECTION
// "GraphRequest preserves non-default sync mode". Class (b): Quiver has one sync mode, so no
// message carries one; the request for a graph is a pull, and its fields (sender, request id,
// the sender's set and context, the whole-state flag) survive the CDR round trip.
TEST(CortexTypeTranslation, WireGraphRequestPreservesNonDefaultSyncMode) {
  PullMsg pull;
  pull.request = 42;
  pull.applied = {Range{ReplicaId{7, 1}, 1, 9}};
  pull.context = {Range{ReplicaId{7, 1}, 1, 30}, Range{ReplicaId{8, 2}, 4, 5}};
  pull.whole_state = true;
  Sample s{ReplicaId{7, 1}, ReplicaId{8, 2}, pull};
  Sample rt = cdr_round_trip(s);
  EXPECT_EQ(rt.from, s.from);
  EXPECT_EQ(rt.to, s.to);
  const auto* p = std::get_if<PullMsg>(&rt.message);
  ASSERT_NE(p, nullptr);
  EXPECT_EQ(p->request, 42u);
  EXPECT_EQ(p->applied, pull.applied);
  EXPECT_EQ(p->context, pull.context);
  EXPECT_TRUE(p->whole_state);
  EXPECT_FALSE(p->as_state);
}

// CORTEX type_translation.cpp, "Wire metadata round-trip preserves sync mode" / SECTION "Node
// delta preserves sync mode". Class (b): no sync mode; a node's delta travels as a DeltaMsg whose
// origin, sequence interval and payload survive the CDR round trip, and the payload still
// decodes to the node.
TEST(CortexTypeTranslation, WireNodeDeltaPreservesSyncMode) {
  Graph g(ReplicaId{3, 1});
  std::vector<GraphDelta> out;
  g.set_delta_sink([&](const GraphDelta& d) { out.push_back(d); });
  auto tx = g.begin();
  NodeId id = tx.create_node("robot", "sync_mode_node").value();
  ASSERT_TRUE(tx.commit().ok());
  ASSERT_EQ(out.size(), 1u);
  DeltaMsg m;
  m.origin = g.replica();
  m.lo = m.hi = 1;
  std::vector<std::uint8_t> payload;
  graph::encode(out[0], payload, 1, 1);
  m.payload = std::make_shared<const std::vector<std::uint8_t>>(payload);
  Sample rt = cdr_round_trip(Sample{g.replica(), ReplicaId{}, m});
  const auto* d = std::get_if<DeltaMsg>(&rt.message);
  ASSERT_NE(d, nullptr);
  EXPECT_EQ(d->origin, m.origin);
  EXPECT_EQ(d->lo, 1u);
  EXPECT_EQ(d->hi, 1u);
  ASSERT_NE(d->payload, nullptr);
  EXPECT_EQ(*d->payload, payload);
  auto decoded = graph::decode(*d->payload);
  ASSERT_TRUE(decoded.ok());
  EXPECT_EQ(decoded->seq_lo, 1u);
  ASSERT_EQ(decoded->nodes.size(), 1u);
  EXPECT_EQ(decoded->nodes[0].id, id);
  EXPECT_EQ(decoded->nodes[0].name, "sync_mode_node");
}

// CORTEX type_translation.cpp, "Wire metadata round-trip preserves sync mode" / SECTION "Full
// graph snapshot preserves sync mode". Class (b): no sync mode; a full graph travels as state
// chunks, whose request id, index, count, sender's set and bytes survive the CDR round trip.
TEST(CortexTypeTranslation, WireFullGraphSnapshotPreservesSyncMode) {
  StateMsg st;
  st.request = 1;
  st.index = 0;
  st.count = 2;
  st.applied = {Range{ReplicaId{1, 1}, 1, 4}};
  st.chunk = std::make_shared<const std::vector<std::uint8_t>>(std::vector<std::uint8_t>{1, 2, 3, 4, 5});
  Sample rt = cdr_round_trip(Sample{ReplicaId{1, 1}, ReplicaId{2, 1}, st});
  EXPECT_EQ(rt.to, (ReplicaId{2, 1}));
  const auto* p = std::get_if<StateMsg>(&rt.message);
  ASSERT_NE(p, nullptr);
  EXPECT_EQ(p->request, 1u);
  EXPECT_EQ(p->index, 0u);
  EXPECT_EQ(p->count, 2u);
  EXPECT_EQ(p->applied, st.applied);
  ASSERT_NE(p->chunk, nullptr);
  EXPECT_EQ(*p->chunk, *st.chunk);
}

// CORTEX type_translation.cpp, "Wire metadata round-trip preserves sync mode" / SECTION "LWW
// node delta preserves delete metadata". Class (b): CORTEX's LWW delete message carries the
// node's type, name, attributes and a deleted flag. A Quiver delete delta names only the id (the
// creation dot it removes); it survives serialization as a removal, and the receiver's change
// batch carries the deleted node's type, name and attribute values from its own copy.
TEST(CortexTypeTranslation, WireLwwNodeDeltaPreservesDeleteMetadata) {
  Graph g(ReplicaId{9, 1});
  std::vector<GraphDelta> out;
  g.set_delta_sink([&](const GraphDelta& d) { out.push_back(d); });
  NodeId id;
  {
    auto tx = g.begin();
    id = tx.create_node("robot", "lww_node", {{"level", Value::int32(7)}}).value();
    ASSERT_TRUE(tx.commit().ok());
  }
  Graph other(ReplicaId{10, 1});
  other.merge(out[0]);
  {
    auto tx = g.begin();
    ASSERT_TRUE(tx.delete_node(id).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  auto decoded = graph::decode(graph::encode(out.back()));
  ASSERT_TRUE(decoded.ok());
  ASSERT_EQ(decoded->nodes.size(), 1u);
  EXPECT_EQ(decoded->nodes[0].id, id);
  EXPECT_TRUE(decoded->nodes[0].removed);
  std::vector<graph::NodeChange> seen;
  other.subscribe([&](const graph::ChangeBatch& b) {
    for (const auto& n : b.nodes) seen.push_back(n);
  });
  other.merge(*decoded);
  EXPECT_FALSE(other.has_node(id));
  ASSERT_EQ(seen.size(), 1u);
  EXPECT_EQ(seen[0].kind, graph::ChangeKind::kDeleted);
  EXPECT_EQ(seen[0].type, Symbol("robot"));
  EXPECT_EQ(seen[0].name, "lww_node");
  ASSERT_EQ(seen[0].values.size(), 1u);
  EXPECT_EQ(seen[0].values[0].first, Symbol("level"));
  EXPECT_EQ(seen[0].values[0].second, Value::int32(7));
}

// CORTEX type_translation.cpp, "Wire metadata round-trip preserves sync mode" / SECTION "LWW full
// graph snapshot preserves tombstone window". Class (b): Quiver keeps no tombstones with a time
// window; a deletion is remembered by the causal context, which a full state carries. The
// serialized state of a replica that deleted a node removes it from a replica that still has it.
TEST(CortexTypeTranslation, WireLwwFullGraphSnapshotPreservesTombstoneWindow) {
  Graph g(ReplicaId{5, 1});
  NodeId root, gone;
  {
    auto tx = g.begin();
    root = tx.create_node("root", "root").value();
    gone = tx.create_node("robot", "gone").value();
    ASSERT_TRUE(tx.commit().ok());
  }
  Graph stale(ReplicaId{6, 1});
  stale.merge(g.state());
  ASSERT_TRUE(stale.has_node(gone));
  {
    auto tx = g.begin();
    ASSERT_TRUE(tx.delete_node(gone).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  auto decoded = graph::decode(graph::encode(g.state()));
  ASSERT_TRUE(decoded.ok());
  EXPECT_EQ(decoded->kind, GraphDelta::Kind::kState);
  EXPECT_EQ(decoded->context, g.context());
  stale.merge(*decoded);
  EXPECT_TRUE(stale.has_node(root));
  EXPECT_FALSE(stale.has_node(gone));
  EXPECT_EQ(stale.node_count(), 1u);
}

// CORTEX type_translation.cpp, "Sync engine interface message aliases compile". Class (b): CORTEX
// checks that its message variants hold each message kind of both engines and the default
// backend info. Quiver has one protocol: its Message variant holds each of the five kinds, each
// named and carried on its own topic.
TEST(CortexTypeTranslation, SyncEngineInterfaceMessageAliasesCompile) {
  agents::Message summary = agents::SummaryMsg{};
  agents::Message delta = DeltaMsg{};
  agents::Message pull = PullMsg{};
  agents::Message state = StateMsg{};
  agents::Message bye = agents::ByeMsg{};
  EXPECT_TRUE(std::holds_alternative<agents::SummaryMsg>(summary));
  EXPECT_TRUE(std::holds_alternative<DeltaMsg>(delta));
  EXPECT_TRUE(std::holds_alternative<PullMsg>(pull));
  EXPECT_TRUE(std::holds_alternative<StateMsg>(state));
  EXPECT_TRUE(std::holds_alternative<agents::ByeMsg>(bye));
  EXPECT_STREQ(agents::message_kind(summary), "summary");
  EXPECT_STREQ(agents::message_kind(delta), "delta");
  EXPECT_STREQ(agents::message_kind(pull), "pull");
  EXPECT_STREQ(agents::message_kind(state), "state");
  EXPECT_STREQ(agents::message_kind(bye), "bye");
  EXPECT_EQ(agents::topic_of(delta), agents::DdsTopic::kDelta);
  EXPECT_EQ(agents::topic_of(state), agents::DdsTopic::kState);
}

// An edge (with or without 4 attributes) between two nodes, made in its own commit.
struct EdgeCase {
  Graph g{ReplicaId{kAgent, 1}};
  std::vector<GraphDelta> out;
  NodeId from, to;
  std::size_t n_attrs = 0;
  explicit EdgeCase(bool with_attrs) {
    g.set_delta_sink([this](const GraphDelta& d) { out.push_back(d); });
    auto tx = g.begin();
    from = tx.create_node("robot", "from").value();
    to = tx.create_node("room", "to").value();
    EXPECT_TRUE(tx.commit().ok());
    auto attrs = with_attrs ? four_attrs() : std::vector<std::pair<Symbol, Value>>{};
    n_attrs = attrs.size();
    auto tx2 = g.begin();
    EXPECT_TRUE(tx2.insert_edge(from, to, Symbol("in"), attrs).ok());
    EXPECT_TRUE(tx2.commit().ok());
  }
  EdgeKey key() const { return EdgeKey{from, to, Symbol("in")}; }
};

void check_edge_round_trip(const EdgeCase& c, const GraphDelta& decoded) {
  ASSERT_EQ(decoded.edges.size(), 1u);
  EXPECT_EQ(decoded.edges[0].key, c.key());
  EXPECT_EQ(decoded.origin, c.g.replica());
  Graph fresh(ReplicaId{kAgent + 1, 1});
  fresh.merge(c.out.front());
  fresh.merge(decoded);
  ASSERT_TRUE(fresh.has_edge(c.from, c.to, "in"));
  EXPECT_EQ(fresh.edge_attr_names(c.key()).size(), c.n_attrs);
  auto version = fresh.edge_version(c.key());
  ASSERT_TRUE(version.has_value());
  EXPECT_EQ(version->replica.agent, kAgent);  // the agent that made it
  EXPECT_EQ(fresh.digest(), c.g.digest());
}

// CORTEX type_translation.cpp, "EDGE: from DSR representation to CRDT and back via
// serialization" / SECTION "User Edge representation". Class (b): no user Edge object; the edge
// is inserted in a graph and its attributes, endpoints, type and author read back.
TEST(CortexTypeTranslation, EdgeUserEdgeRepresentation) {
  for (bool with_attrs : {false, true}) {
    SCOPED_TRACE(with_attrs ? "with attributes" : "without attributes");
    EdgeCase c(with_attrs);
    auto from_edges = c.g.edges_from(c.from);
    ASSERT_EQ(from_edges.size(), 1u);
    EXPECT_EQ(from_edges[0].from, c.from);
    EXPECT_EQ(from_edges[0].to, c.to);
    EXPECT_EQ(from_edges[0].type, Symbol("in"));
    EXPECT_EQ(c.g.edge_attr_names(c.key()).size(), c.n_attrs);
    EXPECT_EQ(c.g.edge_version(c.key())->replica, c.g.replica());
  }
}

// CORTEX type_translation.cpp, "EDGE: ..." / SECTION "Copy edge — CRDT round-trip". Class (a).
TEST(CortexTypeTranslation, EdgeCopyEdgeCrdtRoundTrip) {
  for (bool with_attrs : {false, true}) {
    SCOPED_TRACE(with_attrs ? "with attributes" : "without attributes");
    EdgeCase c(with_attrs);
    const GraphDelta& delta = c.out.back();
    auto bytes = graph::encode(delta);
    auto decoded = graph::decode(bytes);
    ASSERT_TRUE(decoded.ok()) << decoded.error().to_string();
    EXPECT_EQ(graph::encode(*decoded), bytes);
    check_edge_round_trip(c, *decoded);
  }
}

// CORTEX type_translation.cpp, "EDGE: ..." / SECTION "Move edge — CRDT round-trip". Class (a).
TEST(CortexTypeTranslation, EdgeMoveEdgeCrdtRoundTrip) {
  for (bool with_attrs : {false, true}) {
    SCOPED_TRACE(with_attrs ? "with attributes" : "without attributes");
    EdgeCase c(with_attrs);
    GraphDelta moved = std::move(c.out.back());
    auto decoded = graph::decode(graph::encode(moved));
    ASSERT_TRUE(decoded.ok()) << decoded.error().to_string();
    GraphDelta result = std::move(*decoded);
    check_edge_round_trip(c, result);
  }
}

}  // namespace
}  // namespace quiver::cortex_tests
