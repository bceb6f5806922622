// The shared vocabulary (docs/schema.md): the schema file, the check on local commit, the check
// every receiver makes on deltas and states (a remote delta that breaks it is refused and the
// replicas stay equal), attributes that never change their value type silently, and a schema
// inferred from a world.
#include <gtest/gtest.h>

#include "quiver/agents/replica/replication/replicator.h"
#include "quiver/agents/rules/schema/infer.h"
#include "quiver/agents/rules/schema/schema_admission.h"
#include "quiver/agents/rules/schema/schema_checks.h"
#include "quiver/base/hash.h"
#include "quiver/graph/world_file.h"
#include "quiver/sim/agent_host.h"
#include "quiver/sim/simulator.h"
#include "test_net.h"

namespace quiver::agents {
namespace {

using graph::Graph;
using graph::NodeId;
using graph::Value;
using schema::Schema;
using schema::SchemaAdmission;

constexpr const char* kSchema = R"({
  "quiver_schema": 1,
  "node_types": {"object": {}, "mug": {"is": "object"}, "room": {}, "robot": {}, "person": {}},
  "edge_types": {"in": {"from": ["object", "robot"], "to": ["room"]}, "RT": {}},
  "attributes": {
    "battery": {"type": "double", "unit": "1", "min": 0, "max": 1, "on": ["robot"], "writers": ["battery", "panel"]},
    "label":   {"type": "string"},
    "note":    {"type": "any"},
    "since":   {"type": "int64", "on": ["in"]}
  }})";

std::shared_ptr<const Schema> schema_of(const char* text = kSchema) {
  auto s = Schema::parse(text, "test.schema.json");
  EXPECT_TRUE(s.ok()) << s.error().to_string();
  return std::make_shared<const Schema>(*s);
}

bool says(const Status& s, const std::string& what) {
  return !s.ok() && s.error().message.find(what) != std::string::npos;
}

TEST(SchemaTest, ABadSchemaFileSaysWhatAndWhere) {
  struct Case {
    const char* text;
    const char* says;
  } cases[] = {
      {"[]", "a schema is a JSON object with \"quiver_schema\": 1"},
      {R"({"quiver_schema": 2})", "must be 1"},
      {R"({"quiver_schema": 1, "nodes": {}})", "unknown key \"nodes\""},
      {R"({"quiver_schema": 1, "node_types": {"mug": {"is": "object"}}})", "node type 'mug': its base 'object' is not declared"},
      {R"({"quiver_schema": 1, "node_types": {"a": {"is": "b"}, "b": {"is": "a"}}})", "inherits from itself"},
      {R"({"quiver_schema": 1, "edge_types": {"in": {"from": ["ghost"]}}})", "edge type 'in': the node type 'ghost' is not declared"},
      {R"({"quiver_schema": 1, "attributes": {"x": {"type": "float128"}}})", "attribute 'x': unknown value type 'float128'"},
      {R"({"quiver_schema": 1, "attributes": {"x": {"type": "double", "min": 2, "max": 1}}})", "\"min\" is above \"max\""},
      {R"({"quiver_schema": 1, "attributes": {"x": {"type": "double", "on": ["room"]}}})", "\"on\" names 'room'"},
      {R"({"quiver_schema": 1, "attributes": {"x": {"type": "double", "colour": 1}}})", "unknown key \"colour\""},
      {"{", "JSON syntax error"},
      {R"({"quiver_schema": 1, "attributes": {"x": {"type": "double", "max": 5e555}}})", "number overflow"},
  };
  for (const Case& c : cases) {
    auto s = Schema::parse(c.text, "vocab.json");
    ASSERT_FALSE(s.ok()) << c.text;
    EXPECT_NE(s.error().message.find("vocab.json: "), std::string::npos) << s.error().message;
    EXPECT_NE(s.error().message.find(c.says), std::string::npos) << c.text << " -> " << s.error().message;
  }
  // What it writes, it reads back the same.
  auto s = schema_of();
  auto again = Schema::parse(s->to_json(), "again");
  ASSERT_TRUE(again.ok()) << again.error().to_string();
  EXPECT_EQ(again->to_json(), s->to_json());
  EXPECT_TRUE(s->is_a("mug", "object"));
  EXPECT_FALSE(s->is_a("object", "mug"));
}

// Every kind of refusal on a local commit, each naming what broke the schema; the graph stays as
// it was; what the schema allows (subtypes included) commits.
TEST(SchemaTest, ALocalCommitThatBreaksTheSchemaIsRefusedAndChangesNothing) {
  auto s = schema_of();
  Graph g(graph::ReplicaId{fnv1a64("panel"), 1});
  SchemaAdmission adm(s, nullptr);
  g.set_permission_check(adm.commit_check(g.replica().agent));
  g.set_type_change_check(adm.type_change_check());
  NodeId kitchen, robot, mug;
  {
    auto tx = g.begin();
    kitchen = *tx.create_node("room", "kitchen");
    robot = *tx.create_node("robot", "robot", {{"battery", Value(0.5)}, {"label", Value(std::string("shelly"))}});
    mug = *tx.create_node("mug", "mug");
    ASSERT_TRUE(tx.insert_edge(mug, kitchen, "in", {{"since", Value(std::int64_t{3})}}).ok());
    ASSERT_TRUE(tx.insert_edge(robot, kitchen, "in").ok());
    ASSERT_TRUE(tx.commit().ok()) << "a mug is an object: it may be in a room";
  }
  const auto before = g.digest();
  auto refused = [&](auto&& change, const std::string& what) {
    auto tx = g.begin();
    Status st = change(tx);
    if (st.ok()) {
      auto c = tx.commit();
      st = c.ok() ? Status{} : Status(c.error());
    }
    EXPECT_TRUE(says(st, what)) << what << " -> " << (st.ok() ? "committed" : st.error().message);
    if (!st.ok() && st.error().code != ErrorCode::kTypeMismatch) {
      EXPECT_EQ(st.error().code, ErrorCode::kPermissionDenied);
    }
    EXPECT_EQ(g.digest(), before);
  };
  refused([&](graph::Transaction& tx) { return tx.create_node("ghost", "g").ok() ? Status{} : Status(make_error(ErrorCode::kInternal, "?")); },
          "the schema test.schema.json declares no node type 'ghost'");
  refused([&](graph::Transaction& tx) { return tx.set(robot, "colour", Value(std::string("red"))); },
          "declares no attribute 'colour' (node 'robot')");
  refused([&](graph::Transaction& tx) { return tx.set(robot, "battery", Value(1.5)); },
          "bounds the attribute 'battery' to [0, 1] 1; 1.5 is outside");
  refused([&](graph::Transaction& tx) { return tx.set(robot, "battery", Value(std::string("full"))); },
          "holds a double; a string would change its type");
  refused([&](graph::Transaction& tx) { return tx.set(mug, "battery", Value(0.5)); },
          "lets only 'robot' hold the attribute 'battery', not a node 'mug'");
  refused([&](graph::Transaction& tx) { return tx.insert_edge(kitchen, robot, "in"); },
          "lets an edge 'in' start only at 'object', 'robot', not at a 'room'");
  refused([&](graph::Transaction& tx) { return tx.insert_edge(robot, mug, "near"); }, "declares no edge type 'near'");
  // Writers: agent 'panel' may write battery; another agent may not.
  Graph other(graph::ReplicaId{fnv1a64("speech"), 1});
  SchemaAdmission adm2(s, nullptr);
  other.set_permission_check(adm2.commit_check(other.replica().agent));
  {
    auto tx = other.begin();
    ASSERT_TRUE(tx.create_node("robot", "r", {{"battery", Value(0.2)}}).ok());
    auto c = tx.commit();
    EXPECT_TRUE(says(c.ok() ? Status{} : Status(c.error()), "lets only 'battery', 'panel' write the attribute 'battery'"));
  }
  // Allowed: in range, declared "any" changes its type.
  auto tx = g.begin();
  ASSERT_TRUE(tx.set(robot, "battery", Value(0.25)).ok());
  ASSERT_TRUE(tx.set(robot, "note", Value::int32(1)).ok());
  ASSERT_TRUE(tx.commit().ok());
  auto tx2 = g.begin();
  ASSERT_TRUE(tx2.set(robot, "note", Value(std::string("any type"))).ok()) << "\"any\" may change its type";
  ASSERT_TRUE(tx2.commit().ok());
}

// Without a schema, an attribute keeps its value type: DSR refuses a write of another type too.
TEST(SchemaTest, AWriteNeverChangesAnAttributesTypeSilently) {
  Graph g(graph::ReplicaId{fnv1a64("a"), 1});
  NodeId n;
  {
    auto tx = g.begin();
    n = *tx.create_node("robot", "robot", {{"count", Value::int32(3)}});
    ASSERT_TRUE(tx.commit().ok());
  }
  auto tx = g.begin();
  Status s = tx.set(n, "count", Value(2.5f));
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().code, ErrorCode::kTypeMismatch);
  EXPECT_TRUE(says(s, "attribute 'count' of node 'robot' holds a int32; a float would change its type")) << s.error().message;
  EXPECT_TRUE(tx.set(n, "count", Value::int32(4)).ok()) << "the same type is a write";
  ASSERT_TRUE(tx.commit().ok());
  EXPECT_EQ(*g.get<std::int32_t>(n, "count"), 4);
  // Removed first in the same transaction: it starts afresh with the new type.
  auto tx2 = g.begin();
  ASSERT_TRUE(*tx2.remove_attr(n, graph::Symbol("count")));
  ASSERT_TRUE(tx2.set(n, "count", Value(2.5f)).ok());
  ASSERT_TRUE(tx2.commit().ok());
  EXPECT_EQ(*g.get<float>(n, "count"), 2.5f);
}

// Two agents that each write an attribute first, with two types, concurrently: every replica shows
// the same winner (attr()), and attr_values() shows both (docs/schema.md, "Types never change
// silently").
TEST(SchemaTest, ConcurrentWritesOfTwoTypesResolveAlikeEverywhere) {
  Net net;
  const int a = net.add(fnv1a64("left")), b = net.add(fnv1a64("right"));
  net.pump();
  NodeId robot;
  {
    auto tx = net.nodes[a].g->begin();
    robot = *tx.create_node("robot", "robot");
    ASSERT_TRUE(tx.commit().ok());
  }
  net.advance(200'000'000);
  ASSERT_TRUE(net.nodes[b].g->has_node(robot));
  {  // both commit before either hears the other
    auto tx = net.nodes[a].g->begin();
    ASSERT_TRUE(tx.set(robot, "count", Value::int32(3)).ok());
    ASSERT_TRUE(tx.commit().ok());
    auto tx2 = net.nodes[b].g->begin();
    ASSERT_TRUE(tx2.set(robot, "count", Value(2.5f)).ok());
    ASSERT_TRUE(tx2.commit().ok());
  }
  net.advance(2'000'000'000);
  const graph::Value* left = net.nodes[a].g->attr(robot, "count");
  const graph::Value* right = net.nodes[b].g->attr(robot, "count");
  ASSERT_NE(left, nullptr);
  ASSERT_NE(right, nullptr);
  EXPECT_EQ(*left, *right) << "one winner everywhere";
  EXPECT_EQ(net.nodes[a].g->attr_values(robot, graph::Symbol("count")).size(), 2u);
  EXPECT_EQ(net.nodes[b].g->attr_values(robot, graph::Symbol("count")).size(), 2u);
  EXPECT_EQ(net.nodes[a].g->digest(), net.nodes[b].g->digest());
}

// Three replicas: two honest ones with the schema (on commit and on merge) and a rogue one with
// no schema at all. What breaks the schema is refused by both honest replicas, reported, and they
// end equal; what it allows flows.
TEST(SchemaTest, EveryReplicaRefusesARemoteDeltaThatBreaksTheSchemaAndTheyStayEqual) {
  auto s = schema_of();
  Net net;
  const int a = net.add(fnv1a64("panel")), b = net.add(fnv1a64("battery")), rogue = net.add(fnv1a64("panel2"));
  std::vector<std::unique_ptr<SchemaAdmission>> adm;
  for (int i : {a, b}) {
    adm.push_back(std::make_unique<SchemaAdmission>(s, nullptr));
    adm.back()->install(*net.nodes[i].g, *net.nodes[i].rep);
  }
  net.pump();
  NodeId robot;
  {
    auto tx = net.nodes[a].g->begin();
    robot = *tx.create_node("robot", "robot", {{"label", Value(std::string("shelly"))}});
    ASSERT_TRUE(tx.commit().ok());
  }
  net.advance(200'000'000);
  ASSERT_TRUE(net.nodes[rogue].g->has_node(robot));
  // The rogue writes a label of the wrong type and creates a node of a type the schema lacks.
  NodeId ghost;
  {
    auto tx = net.nodes[rogue].g->begin();
    ASSERT_TRUE(tx.remove_attr(robot, graph::Symbol("label")).ok());
    ASSERT_TRUE(tx.set(robot, "label", Value::int32(7)).ok());
    ASSERT_TRUE(tx.commit().ok()) << "it has no schema";
    auto tx2 = net.nodes[rogue].g->begin();
    ghost = *tx2.create_node("ghost", "boo");
    ASSERT_TRUE(tx2.commit().ok());
  }
  net.advance(5'000'000'000);
  for (int i : {a, b}) {
    const Graph& g = *net.nodes[i].g;
    EXPECT_EQ(*g.get<std::string>(robot, "label"), "shelly") << "refused at replica " << i;
    EXPECT_FALSE(g.has_node(ghost));
    EXPECT_GE(net.nodes[i].rep->stats().deltas_refused, 2u);
    bool typed = false, unknown = false;
    for (const Error& e : net.nodes[i].errors) {
      typed = typed || e.message.find("declares the attribute 'label' a string, not a int32") != std::string::npos;
      unknown = unknown || e.message.find("declares no node type 'ghost'") != std::string::npos;
    }
    EXPECT_TRUE(typed && unknown) << "replica " << i << " reports both refusals";
    if (!(typed && unknown))
      for (const Error& e : net.nodes[i].errors) ADD_FAILURE() << e.message;
  }
  EXPECT_EQ(net.nodes[a].g->digest(), net.nodes[b].g->digest());
  // A state transfer from the rogue holds the same: refused too (the digest check pulled it).
  EXPECT_GE(net.nodes[a].rep->stats().states_refused + net.nodes[b].rep->stats().states_refused, 1u);
  // What the schema allows still flows, from anyone.
  {
    auto tx = net.nodes[b].g->begin();
    ASSERT_TRUE(tx.set(robot, "battery", Value(0.75)).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  net.advance(500'000'000);
  EXPECT_EQ(*net.nodes[a].g->get<double>(robot, "battery"), 0.75);
  EXPECT_EQ(net.nodes[a].g->digest(), net.nodes[b].g->digest());
}

// A schema inferred from a world admits that world, and refuses what the world never shows.
TEST(SchemaTest, ASchemaInferredFromAWorldAdmitsIt) {
  const char* world = R"({"quiver_world": 1,
    "nodes": [{"name": "world", "type": "world"}, {"name": "kitchen", "type": "room"},
              {"name": "robot", "type": "robot", "attrs": {"battery": 0.9, "label": "shelly"}},
              {"name": "mug", "type": "mug", "attrs": {"shape_size": {"vec3f": [1, 2, 3]}}}],
    "edges": [{"from": "robot", "to": "kitchen", "type": "in"}, {"from": "mug", "to": "kitchen", "type": "in"}]})";
  Graph g(graph::ReplicaId{fnv1a64("x"), 1});
  ASSERT_TRUE(graph::load_world(g, world, "w.json").ok());
  Schema s;
  schema::infer_from_graph(g, s);
  auto parsed = Schema::parse(s.to_json(), "inferred");
  ASSERT_TRUE(parsed.ok()) << parsed.error().to_string() << "\n" << s.to_json();
  EXPECT_EQ(parsed->node_types().size(), 4u);
  EXPECT_EQ(parsed->edge_types().at("in").from, (std::vector<std::string>{"mug", "robot"}));
  EXPECT_EQ(*parsed->attributes().at("shape_size").type, graph::ValueType::kVec3f);
  auto shared = std::make_shared<const Schema>(*parsed);
  Graph again(graph::ReplicaId{fnv1a64("y"), 1});
  SchemaAdmission adm(shared, nullptr);
  again.set_permission_check(adm.commit_check(again.replica().agent));
  EXPECT_TRUE(graph::load_world(again, world, "w.json").ok());
  auto tx = again.begin();
  ASSERT_TRUE(tx.create_node("person", "p").ok());
  EXPECT_FALSE(tx.commit().ok()) << "no person in that world";
}

class Quiet final : public Agent {
 public:
  explicit Quiet(std::string name) : Agent(std::move(name)) {}
  void setup(AgentContext&) override {}
};

// The simulator's host loads the schema into every agent's replica, as a process does: a commit
// that breaks it is refused where it is made, and what it allows reaches the others.
TEST(SchemaTest, TheSimulatorsHostEnforcesTheSchemaInEveryAgent) {
  std::vector<sim::SimAgentSpec> specs;
  for (const char* name : {"panel", "battery"})
    specs.push_back({name, [name] { return std::make_unique<Quiet>(name); }});
  sim::AgentHostOptions ho;
  ho.seed = 3;
  ho.replicator = sim::SimConfig::default_replicator();
  ho.world_json = R"({"quiver_world": 1, "nodes": [{"name": "robot", "type": "robot"}]})";
  ho.schema = schema_of();
  sim::AgentHost host(std::move(specs), ho);
  ASSERT_TRUE(host.start().ok());
  host.run_until(host.now() + 1'000'000'000);
  Graph& g = *host.graph(0);
  const NodeId robot = *g.find_node("robot");
  {
    auto tx = g.begin();
    ASSERT_TRUE(tx.set(robot, "battery", Value(7.0)).ok());
    auto c = tx.commit();
    ASSERT_FALSE(c.ok());
    EXPECT_TRUE(says(Status(c.error()), "bounds the attribute 'battery' to [0, 1]")) << c.error().message;
  }
  {
    auto tx = g.begin();
    ASSERT_TRUE(tx.set(robot, "battery", Value(0.5)).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  host.run_until(host.now() + 1'000'000'000);
  EXPECT_EQ(*host.graph(1)->get<double>(robot, "battery"), 0.5);
}

}  // namespace
}  // namespace quiver::agents
