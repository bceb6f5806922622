#include "quiver/graph/world_file.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>

namespace quiver::graph {
namespace {

const char* kWorld = R"({
  "quiver_world": 1,
  "nodes": [
    {"name": "world", "type": "world"},
    {"name": "robot", "type": "robot", "attrs": {"battery": 0.75, "label": "shelly", "count": 3,
                                                   "pos": {"vec3f": [1, 2, 3]}, "id": {"uint64": 18446744073709551615},
                                                   "img": {"bytes": "AAEC/w=="}}},
    {"name": "kitchen", "type": "room"}
  ],
  "edges": [{"from": "robot", "to": "kitchen", "type": "in", "attrs": {"since": {"int64": 12}}}],
  "rt": [{"parent": "world", "child": "robot", "translation": [1, 0, 0], "rpy": [0, 0, 1.5707963267948966], "stamp": 5}]
})";

TEST(WorldFileTest, LoadsNodesEdgesRtAndTypedValues) {
  Graph g(ReplicaId{1, 1});
  auto info = load_world(g, kWorld, "test.json");
  ASSERT_TRUE(info.ok()) << info.error().to_string();
  EXPECT_EQ(info->nodes, 3u);
  NodeId robot = *g.find_node("robot");
  EXPECT_EQ(g.get<double>(robot, "battery").value(), 0.75);
  EXPECT_EQ(g.get<std::int64_t>(robot, "count").value(), 3);
  EXPECT_EQ((g.get<Vec3f>(robot, "pos").value()), (Vec3f{1, 2, 3}));
  EXPECT_EQ(g.get<std::uint64_t>(robot, "id").value(), ~0ull);
  EXPECT_EQ(g.get<Bytes>(robot, "img").value(), (Bytes{0, 1, 2, 255}));
  EXPECT_TRUE(g.has_edge(robot, *g.find_node("kitchen"), Symbol("in")));
  auto rt = g.rt_edge(robot);
  ASSERT_TRUE(rt.has_value());
  EXPECT_EQ(rt->parent, *g.find_node("world"));
  EXPECT_NEAR(rt->pose.rotation[0], std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(rt->pose.rotation[3], std::sqrt(0.5), 1e-12);
  EXPECT_EQ(rt->stamp, 5);
}

TEST(WorldFileTest, SaveThenLoadGivesTheSameVisibleGraph) {
  Graph a(ReplicaId{1, 1});
  ASSERT_TRUE(load_world(a, kWorld).ok());
  std::string saved = save_world(a);
  Graph b(ReplicaId{2, 1});
  auto info = load_world(b, saved, "saved.json");
  ASSERT_TRUE(info.ok()) << info.error().to_string();
  EXPECT_EQ(save_world(b), saved);
  NodeId r = *b.find_node("robot");
  EXPECT_EQ(b.attr(r, "pos")->type(), ValueType::kVec3f);
  EXPECT_EQ(b.attr(r, "battery")->type(), ValueType::kDouble);
}

TEST(WorldFileTest, SyntaxErrorsGiveLineAndColumn) {
  Graph g(ReplicaId{1, 1});
  auto r = load_world(g, "{\n  \"quiver_world\": 1,\n  \"nodes\": [ oops ]\n}", "bad.json");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, ErrorCode::kMalformed);
  EXPECT_NE(r.error().message.find("bad.json:3:"), std::string::npos) << r.error().message;
}

TEST(WorldFileTest, NumbersBeyondDoubleRangeAreAnErrorWithALocation) {
  Graph g(ReplicaId{1, 1});
  auto r = load_world(g, "{\"quiver_world\": 1,\n \"nodes\": [{\"name\": \"a\", \"type\": \"x\", \"attrs\": {\"v\": 1E999}}]}",
                      "big.json");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("big.json:2:"), std::string::npos) << r.error().message;
  EXPECT_NE(r.error().message.find("overflow"), std::string::npos) << r.error().message;
}

TEST(WorldFileTest, SemanticErrorsNameTheValueAndChangeNothing) {
  Graph g(ReplicaId{1, 1});
  ASSERT_TRUE(load_world(g, R"({"quiver_world": 1, "nodes": [{"name": "old", "type": "x"}]})").ok());
  Digest128 before = g.digest();
  struct Case {
    const char* json;
    const char* where;
  } cases[] = {
      {R"({"quiver_world": 1, "nodes": [{"name": "a", "type": "x", "attrs": {"p": {"vec3f": [1, 2]}}}]})",
       "/nodes/0/attrs/p"},
      {R"({"quiver_world": 1, "nodes": [{"name": "a", "type": "x", "attrs": {"p": {"quaternion": 1}}}]})",
       "unknown value type 'quaternion'"},
      {R"({"quiver_world": 1, "nodes": [{"name": "a", "type": "x"}], "edges": [{"from": "a", "to": "ghost", "type": "in"}]})",
       "/edges/0/to"},
      {R"({"quiver_world": 1, "nodes": [{"name": "old", "type": "x"}]})", "already has a node named 'old'"},
      {R"({"quiver_world": 2})", "/quiver_world"},
      {R"({"quiver_world": 1, "nodes": [{"name": "a", "type": "x"}, {"name": "b", "type": "x"}],
           "rt": [{"parent": "a", "child": "b"}, {"parent": "b", "child": "a"}]})", "cycle"},
      {R"({"quiver_world": 1, "nodes": [{"name": "a", "type": "x", "attrs": {"n": {"int32": 3000000000}}}]})",
       "int32 range"},
  };
  for (const auto& c : cases) {
    auto r = load_world(g, c.json, "w.json");
    ASSERT_FALSE(r.ok()) << c.json;
    EXPECT_NE(r.error().message.find(c.where), std::string::npos) << r.error().message;
    EXPECT_EQ(g.digest(), before) << "a rejected file changed the graph: " << c.json;
  }
}

TEST(WorldFileTest, FilesOnDisk) {
  Graph g(ReplicaId{1, 1});
  ASSERT_TRUE(load_world(g, kWorld).ok());
  std::string path = ::testing::TempDir() + "/quiver_world_test.json";
  ASSERT_TRUE(save_world_file(g, path).ok());
  Graph h(ReplicaId{2, 1});
  ASSERT_TRUE(load_world_file(h, path).ok());
  EXPECT_EQ(h.node_count(), 3u);
  auto missing = load_world_file(h, "/nonexistent/x.json");
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error().code, ErrorCode::kIo);
  std::remove(path.c_str());
}

}  // namespace
}  // namespace quiver::graph
