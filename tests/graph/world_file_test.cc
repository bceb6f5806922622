#include "quiver/graph/world_file.h"

#include "quiver/graph/codec.h"
#include "quiver/graph/limits.h"

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

namespace quiver::graph {
namespace {

// Defect 7: a string attribute that is not UTF-8 (the API accepts any bytes) is saved in a form
// JSON can hold, and loads back to the same bytes.
TEST(WorldFileTest, TextThatIsNotUtf8SavesAndLoadsBackToTheSameBytes) {
  Graph g(ReplicaId{1, 1});
  const std::string raw("caf\xc3\xa9 \xff\xfe\x00 end", 12);
  auto tx = g.begin();
  NodeId n = *tx.create_node("thing", "n", {{Symbol("raw"), Value(raw)}, {Symbol("ok"), Value("plain")}});
  ASSERT_TRUE(tx.commit().ok());
  std::string text;
  ASSERT_NO_THROW(text = save_world(g));
  EXPECT_NE(text.find("\"base64\""), std::string::npos);
  Graph back(ReplicaId{2, 1});
  auto loaded = load_world(back, text, "saved.json");
  ASSERT_TRUE(loaded.ok()) << loaded.error().to_string();
  EXPECT_EQ(back.get<std::string>(*back.find_node("n"), "raw").value(), raw);
  EXPECT_EQ(back.get<std::string>(*back.find_node("n"), "ok").value(), "plain");
  (void)n;
}

// Defect 2, through world files: names and values beyond the limits table are refused with the
// file and the element named, and the graph is left as it was.
TEST(WorldFileTest, NamesAndValuesBeyondTheLimitsNameTheElement) {
  const std::string long_name(limits::kMaxNameBytes + 1, 'n');
  struct Case {
    std::string doc, where;
  };
  std::vector<Case> cases = {
      {R"({"quiver_world": 1, "nodes": [{"name": ")" + long_name + R"(", "type": "t"}]})", "w.json:/nodes/0"},
      {R"({"quiver_world": 1, "nodes": [{"name": "a", "type": ")" + long_name + R"("}]})", "w.json:/nodes/0"},
      {R"({"quiver_world": 1, "nodes": [{"name": "a", "type": "t", "attrs": {")" + long_name + R"(": 1}}]})",
       "w.json:/nodes/0/attrs"},
      {R"({"quiver_world": 1, "nodes": [{"name": "a", "type": "t"}, {"name": "b", "type": "t"}],
          "edges": [{"from": "a", "to": "b", "type": ")" + long_name + R"("}]})", "w.json:/edges/0"},
      {R"({"quiver_world": 1, "nodes": [{"name": "a", "type": "t", "attrs": {"big": ")" +
           std::string(limits::kMaxValueBytes + 1, 'v') + R"("}}]})", "w.json:/nodes/0"},
  };
  for (const Case& c : cases) {
    Graph g(ReplicaId{1, 1});
    const Digest128 before = g.digest();
    auto r = load_world(g, c.doc, "w.json");
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().message.rfind(c.where, 0), 0u) << r.error().message.substr(0, 200);
    EXPECT_EQ(g.digest(), before);
    if (c.doc.size() > (1u << 20)) continue;  // parsing 64 MiB of JSON once is enough
    auto seed = world_seed(c.doc, "w.json");
    EXPECT_FALSE(seed.ok()) << "the seed path checks the same";
  }
}

TEST(WorldFileTest, ASeedIsTheSameDeltaForTheSameFileAndAnotherForAnother) {
  auto a = world_seed(kWorld, "a.json"), b = world_seed(kWorld, "b.json");
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_EQ(encode(a->delta), encode(b->delta));
  EXPECT_EQ(a->delta.origin.incarnation, 0u);
  std::string other = kWorld;
  other.replace(other.find("shelly"), 6, "robbie");
  auto c = world_seed(other, "c.json");
  ASSERT_TRUE(c.ok());
  EXPECT_FALSE(c->delta.origin == a->delta.origin);
  Graph g(ReplicaId{5, 1});
  g.merge(*decode(encode(a->delta)));
  EXPECT_EQ(g.node_count(), 3u);
  EXPECT_TRUE(g.check_invariants().empty());
}

}  // namespace
}  // namespace quiver::graph
