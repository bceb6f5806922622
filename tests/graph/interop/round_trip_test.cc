// import -> export -> import gives the same world, for every fixture of both formats; exports of
// worlds made in Quiver (ids, CORTEX's bookkeeping attributes, names, values the target format
// cannot hold as they are); worlds carried from one format to the other.

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "quiver/graph/graph.h"
#include "quiver/interop/agm.h"
#include "quiver/interop/dsr.h"
#include "interop_test_util.h"
#include "quiver/base/rng.h"
#include "world_compare.h"

namespace quiver::interop {
namespace {

using graph::Graph;
using graph::NodeId;
using graph::ReplicaId;
using graph::Value;
using testing::world_differences;

std::vector<std::string> fixtures(const std::string& dir) {
  std::vector<std::string> out;
  for (const auto& e : std::filesystem::directory_iterator(testing::fixture(dir)))
    out.push_back(e.path().string());
  std::sort(out.begin(), out.end());
  return out;
}

std::string join(const std::vector<std::string>& lines) {
  std::string s;
  for (const auto& l : lines) s += l + "\n";
  return s;
}

using ImportFn = Result<ImportReport> (*)(Graph&, std::string_view, std::string_view, const ImportOptions&);
using ExportFn = ExportResult (*)(const Graph&, const ExportOptions&);

/// import -> export -> import of every fixture in `dir`: the same world, no warning on the way,
/// and the second export is the text of the first (nothing drifts).
void every_fixture_round_trips(const std::string& dir, std::size_t at_least, ImportFn import, ExportFn export_) {
  const auto files = fixtures(dir);
  ASSERT_GE(files.size(), at_least);
  for (const std::string& f : files) {
    SCOPED_TRACE(f);
    Graph first(ReplicaId{1, 1});
    auto text = read_file("test", f);
    ASSERT_TRUE(text.ok());
    auto r = import(first, *text, f, {});
    ASSERT_TRUE(r.ok()) << r.error().message;
    const ExportResult out = export_(first, {});
    EXPECT_TRUE(out.warnings.empty()) << join(out.warnings);
    Graph second(ReplicaId{2, 1});
    ImportOptions strict;
    strict.strict = true;  // what we write imports without a warning
    auto again = import(second, out.text, "exported", strict);
    ASSERT_TRUE(again.ok()) << again.error().message << "\n" << out.text;
    EXPECT_EQ(join(world_differences(first, second)), "");
    EXPECT_EQ(export_(second, {}).text, out.text);
  }
}

TEST(RoundTripTest, EveryDsrFixture) { every_fixture_round_trips("dsr", 6, import_dsr, export_dsr); }

TEST(RoundTripTest, EveryAgmFixture) { every_fixture_round_trips("agm", 2, import_agm, export_agm); }

TEST(RoundTripTest, ExportedFilesLookLikeTheirFormat) {
  Graph g(ReplicaId{1, 1});
  ASSERT_TRUE(import_agm_file(g, testing::fixture("agm/world.xml")).ok());
  const std::string agm = export_agm(g).text;
  EXPECT_EQ(agm.rfind("<AGMModel>\n\t<symbol id=\"0\" type=\"world\" x=\"0\" y=\"0\">\n", 0), 0u) << agm;
  EXPECT_NE(agm.find("\t\t<attribute key=\"imName\" value=\"world\" />\n"), std::string::npos);
  EXPECT_NE(agm.find("<symbol id=\"7\" type=\"object\" name=\"world_7\">"), std::string::npos);  // a mapped name
  EXPECT_NE(agm.find("<link src=\"1\" dst=\"1\" label=\"moving\" />"), std::string::npos);
  EXPECT_NE(agm.find("<linkAttribute key=\"engine\" value=\"static\" />"), std::string::npos);
  EXPECT_EQ(agm.find("agm_id"), std::string::npos);
  const std::string dsr = export_dsr(g).text;
  EXPECT_EQ(dsr.rfind("{\n    \"DSRModel\": {\n        \"symbols\": {\n            \"1\": {", 0), 0u) << dsr.substr(0, 200);
  EXPECT_NE(dsr.find("\"rt_translation\": {\n"), std::string::npos);
}

// A world made in Quiver: no source ids, Quiver's own types, names the formats do not derive.
void quiver_world(Graph& g) {
  auto tx = g.begin();
  NodeId world = *tx.create_node("world", "world");
  NodeId robot = *tx.create_node("robot", "robot",
                                 {{graph::Symbol("battery"), Value(0.75)},
                                  {graph::Symbol("count"), Value(std::int64_t{7})},
                                  {graph::Symbol("big"), Value(std::int64_t{1} << 40)},
                                  {graph::Symbol("gains"), Value(graph::DoubleVec{0.5, 0.25})},
                                  {graph::Symbol("label"), Value("shelly")}});
  NodeId cup = *tx.create_node("cup", "cup", {{graph::Symbol("dsr_id"), Value(std::uint64_t{40})}});
  graph::Pose X;
  X.translation = {1.5, -0.25, 0.125};
  X.rotation = {std::sqrt(0.5), 0, 0, std::sqrt(0.5)};
  (void)tx.set_rt(world, robot, X, 0);
  (void)tx.set_rt(robot, cup, graph::Pose{}, 0);
  (void)tx.insert_edge(robot, cup, "sees", {{"confidence", Value(0.5)}});
  (void)tx.insert_edge(robot, robot, "moving");
  ASSERT_TRUE(tx.commit().ok());
}

TEST(RoundTripTest, AQuiverWorldToCortexAndBack) {
  Graph g(ReplicaId{1, 1});
  quiver_world(g);
  const ExportResult out = export_dsr(g);
  // int64 and double vectors have no CORTEX type: written as the nearest one, with a warning.
  EXPECT_NE(join(out.warnings).find("node 'robot' attribute 'big': an int64 (CORTEX has no int64): written as a uint64"),
            std::string::npos)
      << join(out.warnings);
  EXPECT_NE(join(out.warnings).find("attribute 'gains': a double_vec (CORTEX has no vector of doubles)"), std::string::npos);
  Graph back(ReplicaId{2, 1});
  auto r = import_dsr(back, out.text);
  ASSERT_TRUE(r.ok()) << r.error().message;
  // The cup keeps its dsr_id; the others get fresh ids above it, in name order.
  EXPECT_EQ(*back.attr(*back.find_node("cup"), "dsr_id"), Value(std::uint64_t{40}));
  EXPECT_EQ(*back.attr(*back.find_node("robot"), "dsr_id"), Value(std::uint64_t{41}));
  EXPECT_EQ(*back.attr(*back.find_node("world"), "dsr_id"), Value(std::uint64_t{42}));
  // Nodes made in Quiver get CORTEX's bookkeeping: level (RT depth) and parent (RT parent's id);
  // the cup came from CORTEX (it has a dsr_id) and is written as it is.
  EXPECT_EQ(*back.attr(*back.find_node("robot"), "level"), Value::int32(1));
  EXPECT_EQ(*back.attr(*back.find_node("robot"), "parent"), Value(std::uint64_t{42}));
  EXPECT_EQ(*back.attr(*back.find_node("world"), "level"), Value::int32(0));
  EXPECT_EQ(back.attr(*back.find_node("cup"), "level"), nullptr);
  EXPECT_EQ(*back.attr(*back.find_node("robot"), "count"), Value::int32(7));
  EXPECT_EQ(*back.attr(*back.find_node("robot"), "big"), Value(std::uint64_t{1} << 40));
  EXPECT_EQ(*back.attr(*back.find_node("robot"), "gains"), Value(graph::FloatVec{0.5f, 0.25f}));
  EXPECT_TRUE(back.has_edge(*back.find_node("robot"), *back.find_node("robot"), "moving"));
  EXPECT_NEAR(back.rt_edge(*back.find_node("robot"))->pose.translation[0], 1.5, 1e-15);
}

TEST(RoundTripTest, AQuiverWorldToAgmAndBack) {
  Graph g(ReplicaId{1, 1});
  quiver_world(g);
  const ExportResult out = export_agm(g);
  EXPECT_NE(join(out.warnings).find("attribute 'gains': a double_vec becomes the text '0.5 0.25' (AGM attributes are "
                                    "strings; it reads back as a string)"),
            std::string::npos)
      << join(out.warnings);
  // Names that imName or <type>_<id> would not give are written as name="...".
  EXPECT_NE(out.text.find("type=\"robot\" name=\"robot\""), std::string::npos) << out.text;
  Graph back(ReplicaId{2, 1});
  auto r = import_agm(back, out.text);
  ASSERT_TRUE(r.ok()) << r.error().message;
  for (const char* name : {"world", "robot", "cup"}) EXPECT_TRUE(back.find_node(name).has_value()) << name;
  EXPECT_EQ(*back.attr(*back.find_node("robot"), "count"), Value(std::int64_t{7}));
  EXPECT_EQ(*back.attr(*back.find_node("robot"), "battery"), Value(0.75));
  EXPECT_EQ(*back.attr(*back.find_node("cup"), "dsr_id"), Value(std::int64_t{40}));  // an attribute like any
  EXPECT_EQ(*back.edge_attr({*back.find_node("robot"), *back.find_node("cup"), graph::Symbol("sees")}, "confidence"),
            Value(0.5));
  EXPECT_NEAR(back.rt_edge(*back.find_node("robot"))->pose.translation[2], 0.125, 1e-15);
}

TEST(RoundTripTest, FromOneFormatToTheOther) {
  // AGM -> Quiver -> CORTEX -> Quiver: the same structure and poses (values take CORTEX's types).
  Graph agm(ReplicaId{1, 1});
  ASSERT_TRUE(import_agm_file(agm, testing::fixture("agm/world.xml")).ok());
  Graph dsr(ReplicaId{2, 1});
  auto r = import_dsr(dsr, export_dsr(agm).text);
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ(dsr.node_count(), agm.node_count());
  EXPECT_EQ(dsr.edge_count(), agm.edge_count());
  for (NodeId id : agm.nodes()) {
    const std::string name = agm.name_of(id);
    auto other = dsr.find_node(name);
    ASSERT_TRUE(other.has_value()) << name;
    auto a = agm.rt_edge(id), b = dsr.rt_edge(*other);
    ASSERT_EQ(a.has_value(), b.has_value()) << name;
    if (!a) continue;
    EXPECT_EQ(agm.name_of(a->parent), dsr.name_of(b->parent));
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(a->pose.translation[i], b->pose.translation[i], 1e-12) << name;
    const auto ra = testing::rotation_matrix(a->pose), rb = testing::rotation_matrix(b->pose);
    for (int i = 0; i < 9; ++i) EXPECT_NEAR(ra[i], rb[i], 1e-12) << name;
  }
}

TEST(RoundTripTest, RandomPosesSurviveBothFormats) {
  Rng rng(20261124);
  Graph g(ReplicaId{1, 1});
  {
    auto tx = g.begin();
    const NodeId world = *tx.create_node("world", "world");
    NodeId parent = world;
    for (int i = 0; i < 300; ++i) {
      NodeId child = *tx.create_node("frame", "f" + std::to_string(i));
      graph::Pose X;
      for (double& t : X.translation) t = (rng.uniform() - 0.5) * 20;
      double n = 0;
      for (double& q : X.rotation) {
        q = rng.uniform() - 0.5;
        n += q * q;
      }
      for (double& q : X.rotation) q /= std::sqrt(n);
      if (i % 50 == 0) X.rotation = {std::sqrt(0.5), 0, std::sqrt(0.5) * (i % 100 ? 1 : -1), 0};  // gimbal lock
      (void)tx.set_rt(i % 3 == 0 ? parent : world, child, X, 0);
      if (i % 3 == 0) parent = child;
    }
    ASSERT_TRUE(tx.commit().ok());
  }
  for (bool dsr : {true, false}) {
    Graph back(ReplicaId{2, 1});
    auto r = dsr ? import_dsr(back, export_dsr(g).text) : import_agm(back, export_agm(g).text);
    ASSERT_TRUE(r.ok()) << r.error().message;
    for (int i = 0; i < 300; ++i) {
      const std::string name = "f" + std::to_string(i);
      auto a = g.rt_edge(*g.find_node(name)), b = back.rt_edge(*back.find_node(name));
      ASSERT_TRUE(b.has_value());
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(a->pose.translation[k], b->pose.translation[k], 1e-12) << name;
      const auto ra = testing::rotation_matrix(a->pose), rb = testing::rotation_matrix(b->pose);
      for (int k = 0; k < 9; ++k) EXPECT_NEAR(ra[k], rb[k], 1e-12) << name << (dsr ? " dsr" : " agm");
    }
  }
}

}  // namespace
}  // namespace quiver::interop
