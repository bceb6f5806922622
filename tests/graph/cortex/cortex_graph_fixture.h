#pragma once
// Setup helpers shared by the translations of RoboComp CORTEX's tests (tests/graph/cortex/*_test.cc),
// each written once here:
//  - data_path() and load_world(): the Quiver-format copies of CORTEX's test config files in
//    data/ (edge_world.json: make_edge_config_file(), empty_world.json: make_empty_config_file());
//  - CortexGraphTest: a fixture owning a Graph `g`, with DSR's one-call writes as committed
//    transactions (insert_node, set_and_commit, remove_attr_and_commit, insert_edge, ...);
//  - CortexWorldTest: the same, `g` loaded from a world file, with its "root", "room" and
//    "Shadow" nodes looked up (DSR nodes 100, 150 and 200 of the edge config file);
//  - commit() (a transaction's commit as a Status), install_schema() (DSR's type registry as a
//    Quiver schema), written_in() (DSR's local Node copy before update_node);
//  - pose_xyz_euler() and insert_or_assign_rt() (DSR's insert_or_assign_edge_RT);
//  - robot() (CORTEX's make_robot) and Recorder (a Graph that keeps every delta it publishes).

#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "quiver/agents/rules/schema/schema.h"
#include "quiver/agents/rules/schema/schema_admission.h"
#include "quiver/graph/graph.h"
#include "quiver/graph/world_file.h"
#include "quiver/kinematics/eigen_pose.h"

namespace quiver::cortex_tests {

using graph::Dot;
using graph::EdgeKey;
using graph::FloatVec;
using graph::Graph;
using graph::GraphDelta;
using graph::NodeId;
using graph::ReplicaId;
using graph::Symbol;
using graph::Transaction;
using graph::Value;

// An id no node has (DSR's tests use 3333333, 75000, 788987...): no replica writes as agent 777.
inline NodeId absent_id(std::uint64_t counter) { return NodeId{graph::Dot{ReplicaId{777, 1}, counter}}; }

// The path of a file of tests/graph/cortex/data.
inline std::string data_path(const char* file) {
  return (std::filesystem::path(__FILE__).parent_path() / "data" / file).string();
}

// Loads data/<file> into `g` (a fatal failure if it does not load).
inline void load_world(Graph& g, const char* file) {
  auto loaded = graph::load_world_file(g, data_path(file));
  ASSERT_TRUE(loaded.ok()) << loaded.error().to_string();
}

// A transaction's commit as a Status.
inline Status commit(Transaction& tx) {
  auto c = tx.commit();
  if (!c.ok()) return c.error();
  return {};
}

// Installs a schema (docs/schema.md) as the check of every commit of `g`, as DSR checks its
// compiled type registry: a node or edge of an undeclared type is refused with kPermissionDenied.
inline void install_schema(Graph& g, const char* schema_json) {
  auto parsed = agents::schema::Schema::parse(schema_json, "cortex_registry");
  ASSERT_TRUE(parsed.ok()) << parsed.error().to_string();
  auto registry = std::make_shared<const agents::schema::Schema>(*parsed);
  agents::schema::SchemaAdmission adm(registry, nullptr);
  g.set_permission_check(adm.commit_check(g.replica().agent));
  g.set_type_change_check(adm.type_change_check());
}

// DSR's get_attrib_by_name() on the local Node copy before update_node(): the value the open
// transaction (Quiver's local copy) last wrote to the attribute, or null if it wrote none.
inline const Value* written_in(const Transaction& tx, NodeId id, Symbol attr) {
  for (auto op = tx.ops().rbegin(); op != tx.ops().rend(); ++op)
    if (op->kind == graph::TxnOp::Kind::kSetAttr && op->node == id && op->attr == attr) return &op->value;
  return nullptr;
}

// A fixture owning the graph `g` (written as `replica`), with DSR's single-call writes, each one
// committed transaction (DSR's insert_node, update_node, insert_or_assign_edge).
struct CortexGraphTest : ::testing::Test {
  explicit CortexGraphTest(ReplicaId replica) : g(replica) {}

  // DSR's insert_node: the new id, or the error of the creation or the commit.
  Result<NodeId> try_insert_node(std::string_view type, std::string_view name,
                                 std::vector<std::pair<Symbol, Value>> attrs = {}) {
    auto tx = g.begin();
    auto id = tx.create_node(type, name, std::move(attrs));
    if (!id.ok()) return id;
    if (Status s = commit(tx); !s.ok()) return s.error();
    return id;
  }
  // The same, expected to succeed: the new id (a null id, and a failure, if not).
  NodeId insert_node(std::string_view type, std::string_view name) {
    auto tx = g.begin();
    auto id = tx.create_node(type, name);
    EXPECT_TRUE(id.ok()) << id.error().to_string();
    EXPECT_TRUE(tx.commit().ok());
    return id.value_or(NodeId{});
  }
  // DSR's add_or_modify_attrib_local + update_node: one attribute written and committed.
  Status set_and_commit(NodeId id, std::string_view attr, Value v) {
    auto tx = g.begin();
    if (Status s = tx.set(id, attr, std::move(v)); !s.ok()) return s;
    return commit(tx);
  }
  Status set_edge_and_commit(const EdgeKey& key, std::string_view attr, Value v) {
    auto tx = g.begin();
    if (Status s = tx.set_edge_attr(key, attr, std::move(v)); !s.ok()) return s;
    return commit(tx);
  }
  // DSR's remove_attrib_local + update_node: what remove_attrib_local returned (the commit is
  // expected to succeed).
  Result<bool> remove_attr_and_commit(NodeId id, std::string_view attr) {
    auto tx = g.begin();
    auto had = tx.remove_attr(id, attr);
    EXPECT_TRUE(tx.commit().ok());
    return had;
  }
  // DSR's insert_or_assign_edge.
  Status insert_edge(NodeId from, NodeId to, std::string_view type,
                     std::vector<std::pair<Symbol, Value>> attrs = {}) {
    auto tx = g.begin();
    if (Status s = tx.insert_edge(from, to, type, std::move(attrs)); !s.ok()) return s;
    return commit(tx);
  }

  Graph g;
};

// A CortexGraphTest whose graph is loaded from data/<world> before each test; root, room and
// shadow are its nodes "root", "room" and "Shadow" (null ids where the world has none).
struct CortexWorldTest : CortexGraphTest {
  CortexWorldTest(const char* world, ReplicaId replica) : CortexGraphTest(replica), world_(world) {}

  void SetUp() override {
    ASSERT_NO_FATAL_FAILURE(load_world(g, world_));
    root = g.find_node("root").value_or(NodeId{});
    room = g.find_node("room").value_or(NodeId{});
    shadow = g.find_node("Shadow").value_or(NodeId{});
  }

  NodeId root, room, shadow;

 private:
  const char* world_;
};

// X = translation t, then rotation Rx·Ry·Rz (DSR's Euler XYZ angles).
inline Eigen::Isometry3d pose_xyz_euler(const Eigen::Vector3d& t, const Eigen::Vector3d& rxyz) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.translate(t);
  X.rotate(Eigen::AngleAxisd(rxyz.x(), Eigen::Vector3d::UnitX()) * Eigen::AngleAxisd(rxyz.y(), Eigen::Vector3d::UnitY()) *
           Eigen::AngleAxisd(rxyz.z(), Eigen::Vector3d::UnitZ()));
  return X;
}

// DSR's insert_or_assign_edge_RT(n, to, translation, euler_xyz[, covariance], stamp): one RT write
// (with the covariance as the edge attribute rt_covariance, if given), committed.
inline Status insert_or_assign_rt(Graph& g, NodeId parent, NodeId child, const Eigen::Vector3d& t,
                                  const Eigen::Vector3d& rxyz, std::int64_t stamp,
                                  const std::optional<FloatVec>& covariance = std::nullopt) {
  auto tx = g.begin();
  if (Status s = kinematics::set_rt(tx, parent, child, pose_xyz_euler(t, rxyz), stamp); !s.ok()) return s;
  if (covariance) {
    if (Status s = tx.set_edge_attr(EdgeKey{parent, child, graph::symbols::rt()}, "rt_covariance", Value(*covariance));
        !s.ok())
      return s;
  }
  return commit(tx);
}

// CORTEX's make_robot: a "robot" node with level 0.
inline NodeId robot(Transaction& tx, const std::string& name, std::int32_t level = 0) {
  auto id = tx.create_node("robot", name, {{"level", Value::int32(level)}});
  EXPECT_TRUE(id.ok()) << id.error().to_string();
  return id.value_or(NodeId{});
}

// A graph that records every delta it publishes (what CORTEX's sync engine hands its network).
struct Recorder {
  Graph g;
  std::vector<GraphDelta> out;
  explicit Recorder(std::uint64_t agent) : g(ReplicaId{agent, 1}) {
    g.set_delta_sink([this](const GraphDelta& d) { out.push_back(d); });
  }
  // Runs `f` in a transaction, commits it and returns the delta it published.
  template <class F>
  GraphDelta write(F&& f) {
    auto tx = g.begin();
    f(tx);
    const std::size_t before = out.size();
    auto c = tx.commit();
    EXPECT_TRUE(c.ok()) << c.error().to_string();
    EXPECT_EQ(out.size(), before + 1) << "the commit published no delta";
    return out.empty() ? GraphDelta{} : out.back();
  }
};

}  // namespace quiver::cortex_tests
