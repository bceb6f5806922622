#pragma once
// The fixture shared by the translations of RoboComp CORTEX tests/src/test_dsr_api.cpp
// (dsr_api_nodes_test.cc, dsr_api_edges_test.cc, dsr_api_attributes_test.cc; docs/dsr-api.md maps
// each DSR call): the CortexDsrApi fixture and the graph names they use.
//
// CORTEX's sections share one DSRGraph loaded from testfiles/example.json (node 1 the root, node
// 2 its RT child) and lean on what earlier sections left behind. Here every test builds its own
// graph with the same shape (CortexDsrApi fixture): "root" (DSR's node 1) with an RT child "child"
// (node 2), and "lonely", a node without edges (node 1000); what a section relied on from an
// earlier one is set up in the test. DSR's registered attribute types map to Quiver's value types
// (test_int: int32, test_uint: uint32, ...). DSR reports errors by exceptions or false/nullopt;
// Quiver by Status/Result values (an error code) or nullopt.

#include <cstdint>
#include <string>
#include <string_view>
#include <utility>

#include "cortex_graph_fixture.h"

namespace quiver::cortex_tests {

using graph::Pose;

struct CortexDsrApi : CortexGraphTest {
  CortexDsrApi() : CortexGraphTest(ReplicaId{1111, 1}) {}

  NodeId root, child, lonely;

  void SetUp() override {
    auto tx = g.begin();
    root = tx.create_node("world", "root").value();
    child = tx.create_node("robot", "child").value();
    lonely = tx.create_node("test_n", "lonely").value();
    ASSERT_TRUE(tx.set_rt(root, child, Pose::identity(), 1).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  NodeId create(const std::string& type, const std::string& name) { return insert_node(type, name); }
  // DSR's add_or_modify_attrib_local + update_node.
  Status set(NodeId id, std::string_view attr, Value v) { return set_and_commit(id, attr, std::move(v)); }
  Result<bool> remove(NodeId id, std::string_view attr) { return remove_attr_and_commit(id, attr); }
  EdgeKey rt_key() const { return EdgeKey{root, child, graph::symbols::rt()}; }
  // DSR's type registry (built-in "world" and "robot", the file's REGISTER_NODE_TYPE(test_n) and
  // REGISTER_EDGE_TYPE(test_e), and "RT") as Quiver's schema (docs/schema.md), checked on every
  // commit of `g`: a node or edge of an undeclared type is refused with kPermissionDenied.
  void install_registry() {
    install_schema(g, R"({"quiver_schema": 1, "node_types": {"world": {}, "robot": {}, "test_n": {}},
            "edge_types": {"test_e": {}, "RT": {}}})");
  }
};

}  // namespace quiver::cortex_tests
