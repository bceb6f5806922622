// Keeps docs/dsr-api.md honest: every Quiver C++ name in its table is called here, in the
// table's order (row numbers in the comments), so a rename breaks this build, not the reader.
// The calls that need a DDS domain are compiled (dds_rows) but not run; the rest run on a local
// graph.

#include <gtest/gtest.h>

#include <future>

#include "quiver/agents/runtime/process/dds_replica.h"
#include "quiver/agents/rules/schema/schema_admission.h"
#include "quiver/agents/runtime/engine/engine.h"
#include "quiver/agents/runtime/process/process_host.h"
#include "quiver/interop/dsr.h"
#include "quiver/graph/world_file.h"
#include "quiver/kinematics/eigen_pose.h"
#include "quiver/kinematics/frames.h"

namespace quiver {
namespace {

using agents::DdsReplica;
using graph::ChangeBatch;
using graph::ChangeFilter;
using graph::EdgeKey;
using graph::Graph;
using graph::NodeId;
using graph::Symbol;
using graph::Value;

// Rows that need a live DDS domain: compiled, never called.
[[maybe_unused]] void dds_rows() {
  agents::DdsReplicaOptions o;
  o.name = "agent";                                   // 1 DSRGraph(name, id, file)
  auto r = DdsReplica::create(o);                     // 1
  DdsReplica& rep = **r;
  Graph& g = rep.graph();                             // 1
  (void)rep.id();                                     // 2 get_agent_id
  (void)rep.options().name;                           // 3 get_agent_name
  for (const agents::PeerInfo& p : rep.replicator().peers()) (void)p.name;  // 4 get_connected_agents
  (void)rep.replicator().name_of(g.replica());        // 30 SignalInfo::agent_id -> name
  std::future<int> f = rep.call([] { return 1; });    // 33 (Qt event loop) -> call
  rep.post([] {});                                    // 33
  DdsReplica::TimerId t = rep.every(10'000'000, [] {});  // 34 QTimer
  rep.after(10'000'000, [] {});                       // 34
  rep.cancel(t);                                      // 34
  rep.spin();                                         // 35 app.exec()
  rep.stop();                                         // 35
  agents::request_stop();                             // 35 (an agent process)
}

// Rows that read or write files: compiled, never called.
[[maybe_unused]] void file_rows(Graph& g) {
  (void)interop::export_dsr_file(g, "world.json");    // 31 write_to_json_file (DSR's JSON)
  (void)interop::import_dsr_file(g, "world.json");    // 32 read_from_json_file (DSR's JSON)
}

// Rows of the runtime's agent API: compiled, never called.
[[maybe_unused]] void agent_rows(agents::Agent& a, agents::AgentContext& ctx) {
  a.subscribe(ChangeFilter{{"person"}, {}, {}},       // 29 connect(signal, slot), filtered
              [](agents::AgentContext&, const ChangeBatch&) {});
  std::future<void> f = a.call([] {});                // 33
  ctx.every(10'000'000, [] {});                       // 34
  ctx.after(10'000'000, [] {});                       // 34
  (void)ctx.hears("speech");                          // 4
}

TEST(DsrApiTable, EveryListedNameCompilesAndRuns) {
  Graph g(graph::ReplicaId{1, 1});
  NodeId root, robot, person;
  {
    auto tx = g.begin();
    root = tx.create_node("world", "root").value();                                   // 9 insert_node
    robot = tx.create_node("robot", "robot", {{"speed", 0.5}}).value();               // 9
    person = tx.create_node("person", "patient").value();                              // 9
    EXPECT_TRUE(tx.set(robot, "battery", 0.9).ok());                                   // 10, 19 update_node / add_or_modify_attrib_local
    const Status added = tx.add(robot, graph::Symbol("battery"), Value(0.8));           // 19 add_attrib_local
    EXPECT_TRUE(!added.ok() && added.error().code == ErrorCode::kAlreadyExists);
    const Status modified = tx.modify(robot, graph::Symbol("mood"), Value(1.0));         // 19 modify_attrib_local
    EXPECT_TRUE(!modified.ok() && modified.error().code == ErrorCode::kNotFound);
    EXPECT_TRUE(tx.remove_attr(robot, "battery").ok());                                // 20 remove_attrib_local
    EXPECT_TRUE(tx.insert_edge(robot, person, "is_with", {{"distance", 1.2}}).ok());   // 14 insert_or_assign_edge
    EXPECT_TRUE(tx.set_edge_attr(EdgeKey{robot, person, Symbol("is_with")}, "distance", 1.0).ok());  // 14, 19
    EXPECT_TRUE(tx.remove_edge_attr(EdgeKey{robot, person, Symbol("is_with")}, "distance").ok());    // 20
    graph::Pose X_WR;
    X_WR.translation = {1.0, 2.0, 0.0};
    EXPECT_TRUE(tx.set_rt(root, robot, X_WR, 1).ok());                                 // 22 insert_or_assign_edge_RT
    EXPECT_TRUE(kinematics::set_rt(tx, root, person, Eigen::Isometry3d::Identity(), 1).ok());  // 22
    EXPECT_TRUE(tx.commit().ok());                                                     // (the DSR call's own publish)
  }
  EXPECT_TRUE(g.find_node("robot").has_value());                                       // 5 get_node(name), 7 get_id_from_name
  EXPECT_TRUE(g.has_node(robot));                                                      // 5 get_node(id)
  EXPECT_EQ(g.name_of(robot), "robot");                                                // 6 get_name_from_id
  EXPECT_EQ(g.type_of(robot).str(), "robot");                                          // 6 node.type()
  EXPECT_EQ(g.rt_roots().size(), 1u);                                                  // 8 get_node_root
  EXPECT_EQ(g.nodes_of_type("robot").size(), 1u);                                      // 11 get_nodes_by_type
  EXPECT_EQ(g.nodes().size(), 3u);                                                     // 12 getCopy / nodes
  EXPECT_EQ(g.attr_names(robot).size(), 1u);                                           // 12 node.attrs
  EXPECT_TRUE(g.has_edge(robot, person, "is_with"));                                   // 13 get_edge
  EXPECT_EQ(g.edges_of_type("is_with").size(), 1u);                                    // 16 get_edges_by_type
  EXPECT_EQ(g.edges_to(person).size(), 2u);                                            // 17 get_edges_to_id
  EXPECT_EQ(g.edges_from(robot, "is_with").size(), 1u);                                // 17 get_edges / node.edges
  EXPECT_EQ(g.get<double>(robot, "speed").value(), 0.5);                               // 18 get_attrib_by_name
  EXPECT_NE(g.attr(robot, "speed"), nullptr);                                          // 18
  EXPECT_EQ(g.attr_values(robot, Symbol("speed")).size(), 1u);                         // 18 (all concurrent values)
  EXPECT_FALSE(g.get<double>(EdgeKey{robot, person, Symbol("is_with")}, "distance").ok());  // 18 (edges)
  EXPECT_EQ(g.edge_attr(EdgeKey{robot, person, Symbol("is_with")}, "distance"), nullptr);  // 18
  EXPECT_EQ(g.rt_parent(robot).value(), root);                                         // 21 get_parent_id / get_parent_node
  EXPECT_EQ(g.rt_children(root).size(), 2u);                                           // 21
  EXPECT_EQ(g.rt_level(robot).value(), 1u);                                            // 21 get_node_level
  EXPECT_EQ(g.node_count(), 3u);                                                       // 38 size
  ASSERT_TRUE(g.rt_edge(robot).has_value());                                           // 23 get_edge_RT
  EXPECT_EQ(g.rt_history(robot).size(), 1u);                                           // 23 (timed RT history)
  EXPECT_EQ(kinematics::translation(g.rt_edge(robot)->pose).x(), 1.0);                 // 24 get_translation(n, to)
  EXPECT_TRUE(kinematics::rt_transform(g, robot).has_value());                         // 24 get_RT_pose_from_parent
  (void)kinematics::rotation_matrix(g.rt_edge(robot)->pose);                           // 24
  (void)kinematics::rotation(g.rt_edge(robot)->pose);                                  // 24
  (void)kinematics::to_pose(kinematics::to_isometry(g.rt_edge(robot)->pose));          // 24
  kinematics::FrameTree tree(g);
  EXPECT_TRUE(tree.lookup("root", "robot").ok());                                      // 25 get_transformation_matrix
  EXPECT_TRUE(tree.translation("root", "robot").ok());                                 // 25 get_translation_vector
  EXPECT_TRUE(tree.rotation("root", "robot").ok());                                    // 25 get_rotation_matrix
  EXPECT_TRUE(tree.transform_point("root", "robot", Eigen::Vector3d::Zero()).ok());    // 26 transform
  EXPECT_TRUE(tree.transform_pose("root", "robot", Eigen::Isometry3d::Identity()).ok());  // 26 transform_axis
  EXPECT_TRUE(tree.lookup_at("root", "robot", 1).ok());                                // 25 (timestamp argument)

  std::vector<ChangeBatch> seen;
  auto sub = g.subscribe([&](const ChangeBatch& b) { seen.push_back(b); });            // 28 connect(update_*_signal)
  g.subscribe(ChangeFilter{{}, {"is_with"}, {}}, [&](const ChangeBatch&) {});          // 29 filtered
  {
    auto tx = g.begin();
    EXPECT_TRUE(tx.delete_edge(robot, person, "is_with").ok());                        // 15 delete_edge
    EXPECT_TRUE(tx.delete_node(person).ok());                                          // 27 delete_node
    EXPECT_TRUE(tx.commit().ok());
  }
  ASSERT_EQ(seen.size(), 1u);
  EXPECT_FALSE(seen[0].origin_name.empty());                                           // 30 SignalInfo
  EXPECT_TRUE(seen[0].local);                                                          // 30
  g.unsubscribe(sub);                                                                  // 28 disconnect
  const std::string json = graph::save_world(g);                                       // 31 write_to_json_file
  Graph h(graph::ReplicaId{2, 1});
  EXPECT_TRUE(graph::load_world(h, json).ok());                                        // 32 read_from_json_file
  EXPECT_EQ(Value(4).type(), graph::ValueType::kInt64);                                // 36 Attribute(int)
  EXPECT_EQ(Value::int32(4).type(), graph::ValueType::kInt32);                         // 36
  auto vocabulary = agents::schema::Schema::parse(R"({"quiver_schema": 1, "open": true})", "s");  // 37 type registry
  ASSERT_TRUE(vocabulary.ok());
  g.set_type_change_check([](graph::Symbol) { return false; });                        // 37
  EXPECT_EQ(g.check_invariants().size(), 0u);
}

}  // namespace
}  // namespace quiver
