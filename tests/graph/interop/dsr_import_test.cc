// CORTEX DSR JSON import: every layout, every type code, history packs, RT link attributes,
// self-loops, CORTEX's quirks (warnings), names, and malformed files (errors that name the file
// and the element, nothing half-imported).

#include <gtest/gtest.h>

#include <string>

#include "interop_test_util.h"
#include "quiver/graph/graph.h"
#include "quiver/interop/dsr.h"
#include "quiver/interop/interop.h"

namespace quiver::interop {
namespace {

using graph::Graph;
using graph::NodeId;
using graph::ReplicaId;
using graph::Value;
using namespace testing;

std::string dsr_error_of(const std::string& text, const std::string& source = "dsr.json") {
  return refusal(import_dsr, text, source);
}

TEST(DsrImportTest, CurrentLayoutWithEveryTypeCode) {
  Graph g(ReplicaId{1, 1});
  ImportOptions strict;
  strict.strict = true;  // the file is clean: no warning
  auto r = import_dsr_file(g, fixture("dsr/current_layout.json"), strict);
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_TRUE(r->warnings.empty());
  EXPECT_EQ(r->nodes, 5u);
  EXPECT_EQ(r->edges, 3u);
  EXPECT_EQ(r->rt_edges, 4u);
  EXPECT_EQ(g.type_of(node(g, "robot")).str(), "omnirobot");
  // Codes 0 to 13, each to its Quiver type.
  EXPECT_EQ(attr(g, "robot", "s"), Value("shelly"));
  EXPECT_EQ(attr(g, "robot", "i32"), Value::int32(-42));
  EXPECT_EQ(attr(g, "robot", "f"), Value(1.25f));  // "1,25": CORTEX's reader takes ',' for '.'
  EXPECT_EQ(attr(g, "robot", "fv"), Value(graph::FloatVec{0.5f, 1.5f, -2.f}));
  EXPECT_EQ(attr(g, "robot", "b"), Value(true));
  EXPECT_EQ(attr(g, "robot", "bytes"), Value(graph::Bytes{0, 127, 255}));
  EXPECT_EQ(attr(g, "robot", "u32"), Value::uint32(4294967295u));  // written as the int32 -1
  EXPECT_EQ(attr(g, "robot", "u64"), Value(std::uint64_t{18446744073709551615u}));
  EXPECT_EQ(attr(g, "robot", "d"), Value(0.1));
  EXPECT_EQ(attr(g, "robot", "u64v"), Value(graph::UInt64Vec{1, 18446744073709551615u}));
  EXPECT_EQ(attr(g, "robot", "v2"), Value(graph::Vec2f{1, 2}));
  EXPECT_EQ(attr(g, "robot", "v3"), Value(graph::Vec3f{1, 2, 3}));
  EXPECT_EQ(attr(g, "robot", "v4"), Value(graph::Vec4f{1, 2, 3, 4}));
  EXPECT_EQ(attr(g, "robot", "v6"), Value(graph::Vec6f{1, 2, 3, 4, 5, 6}));
  EXPECT_EQ(attr(g, "robot", "level"), Value::int32(1));  // code and value as strings
  EXPECT_EQ(attr(g, "robot", "parent"), Value(std::uint64_t{1}));
  EXPECT_EQ(attr(g, "robot", "dsr_id"), Value(std::uint64_t{2}));
  // Link attributes.
  const graph::EdgeKey carries{node(g, "robot"), node(g, "mug"), graph::Symbol("carries")};
  ASSERT_TRUE(g.has_edge(carries.from, carries.to, carries.type));
  EXPECT_EQ(*g.edge_attr(carries, "grip"), Value(0.25f));
  EXPECT_EQ(*g.edge_attr(carries, "n"), Value::int32(3));
  EXPECT_EQ(*g.edge_attr(carries, "pose6"), Value(graph::Vec6f{0, 0, 0.1f, 0, 0, 1.5f}));
  EXPECT_EQ(*g.edge_attr(carries, "tag"), Value("left hand"));
  // Self-loops are edges (unary predicates), with their attributes.
  ASSERT_TRUE(g.has_edge(node(g, "world"), node(g, "world"), "explored"));
  EXPECT_EQ(*g.edge_attr({node(g, "world"), node(g, "world"), graph::Symbol("explored")}, "since"), Value(12.5));
  EXPECT_TRUE(g.has_edge(node(g, "robot"), node(g, "robot"), "moving"));
  // RT parents.
  EXPECT_EQ(g.rt_parent(node(g, "robot")), node(g, "world"));
  EXPECT_EQ(g.rt_parent(node(g, "arm")), node(g, "robot"));
  EXPECT_EQ(g.rt_parent(node(g, "hand")), node(g, "arm"));
  EXPECT_EQ(g.rt_parent(node(g, "mug")), node(g, "world"));
}

TEST(DsrImportTest, HistoryPackGivesItsNewestSampleAndTheLinkKeepsItsOtherAttributes) {
  Graph g(ReplicaId{1, 1});
  ASSERT_TRUE(import_dsr_file(g, fixture("dsr/current_layout.json")).ok());
  // Four samples; rt_timestamps says the third is the newest (rt_head_index points elsewhere:
  // files differ on whether it names the newest sample or the next slot; time stamps decide).
  const auto rt = g.rt_edge(node(g, "arm"));
  ASSERT_TRUE(rt.has_value());
  EXPECT_NEAR(rt->pose.translation[0], 0.1, 1e-15);
  EXPECT_NEAR(rt->pose.translation[1], 0.2, 1e-15);
  EXPECT_NEAR(rt->pose.translation[2], 0.3, 1e-15);
  EXPECT_EQ(rt->stamp, 0);
  // Its other attributes are on the child, prefixed; the pack's bookkeeping is consumed.
  EXPECT_EQ(attr(g, "arm", "rt:calibrated"), Value(true));
  EXPECT_EQ(attr(g, "arm", "rt:rt_translation_velocity"), Value(graph::FloatVec{1, 2, 3}));
  EXPECT_EQ(g.attr(node(g, "arm"), "rt:rt_timestamps"), nullptr);
  EXPECT_EQ(g.attr(node(g, "arm"), "rt:rt_head_index"), nullptr);
  EXPECT_EQ(g.attr(node(g, "arm"), "rt:rt_translation"), nullptr);
}

std::string pack(const std::string& extra) {
  return R"({"DSRModel": {"symbols": {
    "1": {"id": "1", "name": "a", "type": "t", "links": [{"src": "1", "dst": "2", "label": "RT", "linkAttribute": {
      "rt_translation": {"type": 3, "value": [1000, 0, 0, 2000, 0, 0, 3000, 0, 0]},
      "rt_rotation_euler_xyz": {"type": 3, "value": [0, 0, 0, 0, 0, 0, 0, 0, 0]})" +
         extra + R"(}}]},
    "2": {"id": "2", "name": "b", "type": "t"}}}})";
}

double x_of_b(const std::string& text, ImportReport* report = nullptr) {
  Graph g(ReplicaId{1, 1});
  auto r = import_dsr(g, text);
  EXPECT_TRUE(r.ok()) << r.error().message;
  if (!r.ok()) return -1;
  if (report) *report = *r;
  return g.rt_edge(*g.find_node("b"))->pose.translation[0];
}

TEST(DsrImportTest, NewestSampleOfAPack) {
  // By time stamps.
  EXPECT_DOUBLE_EQ(x_of_b(pack(R"(, "rt_timestamps": {"type": 9, "value": ["5", "9", "7"]})")), 2.0);
  // By head index without time stamps, or when they tell nothing (all equal).
  EXPECT_DOUBLE_EQ(x_of_b(pack(R"(, "rt_head_index": {"type": 1, "value": 6})")), 3.0);
  EXPECT_DOUBLE_EQ(
      x_of_b(pack(R"(, "rt_head_index": {"type": 1, "value": 3}, "rt_timestamps": {"type": 9, "value": [0, 0, 0]})")),
      2.0);
  // Neither: the first sample, as CORTEX reads it, with a warning.
  ImportReport r;
  EXPECT_DOUBLE_EQ(x_of_b(pack(""), &r), 1.0);
  EXPECT_TRUE(has_warning(r, "history pack of 3 samples without time stamps")) << r.warnings.size();
  // Malformed packs.
  EXPECT_NE(dsr_error_of(pack(R"(, "rt_head_index": {"type": 1, "value": 4})")).find("rt_head_index: expected the index"),
            std::string::npos);
  EXPECT_NE(dsr_error_of(pack(R"(, "rt_timestamps": {"type": 9, "value": [1, 2]})")).find("one time stamp per sample (3)"),
            std::string::npos);
}

TEST(DsrImportTest, HistoricalSymbolObjectWithStringCodesAndAByteOrderMark) {
  Graph g(ReplicaId{1, 1});
  auto r = import_dsr_file(g, fixture("dsr/symbol_object_string_codes.json"));
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_TRUE(r->warnings.empty());
  EXPECT_EQ(r->nodes, 3u);
  EXPECT_EQ(r->rt_edges, 2u);
  EXPECT_EQ(attr(g, "world", "pos_x"), Value(-90.295357f));
  EXPECT_EQ(attr(g, "base", "collide"), Value("false"));  // code 0: a string, whatever it says
  EXPECT_EQ(attr(g, "base", "parent"), Value::int32(100));
  // "trans"/"rot" and "translation"/"rotation_euler_xyz" are poses too.
  EXPECT_NEAR(g.rt_edge(node(g, "base"))->pose.translation[0], -1.6146500244140625, 1e-15);
  EXPECT_NEAR(g.rt_edge(node(g, "laser"))->pose.translation[1], 0.21, 1e-15);
}

TEST(DsrImportTest, ArraysWithATopLevelLinkArrayAndUntypedValues) {
  Graph g(ReplicaId{1, 1});
  auto r = import_dsr_file(g, fixture("dsr/array_top_level_links.json"));
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ(r->nodes, 3u);
  EXPECT_EQ(r->edges, 1u);
  EXPECT_EQ(r->rt_edges, 2u);
  // Values without a type code are typed by their content, with CORTEX's types.
  EXPECT_EQ(attr(g, "base", "port"), Value::int32(10004));
  EXPECT_EQ(attr(g, "base", "noise"), Value(0.5));
  EXPECT_EQ(attr(g, "base", "collide"), Value(false));
  EXPECT_EQ(attr(g, "base", "imType"), Value("differentialrobot"));
  EXPECT_EQ(attr(g, "base", "pos_y"), Value("-168,177170"));  // not a number by content
  EXPECT_EQ(attr(g, "base", "serial"), Value(std::uint64_t{12345678901234567890u}));
  // tx ty tz rx ry rz as strings ("2500,5": a decimal comma).
  const auto rt = g.rt_edge(node(g, "base"));
  EXPECT_NEAR(rt->pose.translation[0], -1.0, 1e-15);
  EXPECT_NEAR(rt->pose.translation[2], 2.5005, 1e-15);
  EXPECT_EQ(*g.edge_attr({node(g, "hokuyo_base"), node(g, "world"), graph::Symbol("sees")}, "distance"), Value(3.5));
}

TEST(DsrImportTest, ArraysOfTypedEntriesWithLinksInsideSymbols) {
  Graph g(ReplicaId{1, 1});
  auto r = import_dsr_file(g, fixture("dsr/array_typed_entries.json"));
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ(attr(g, "world", "pos_x"), Value(-246.617584f));
  EXPECT_EQ(attr(g, "world", "scale"), Value(graph::FloatVec{1, 2.5f, -3}));  // code 3 as a string of numbers
  EXPECT_EQ(*g.edge_attr({node(g, "world"), node(g, "table"), graph::Symbol("near")}, "d"), Value(0.5f));
  EXPECT_NEAR(g.rt_edge(node(g, "table"))->pose.translation[0], 0.1, 1e-15);
}

TEST(DsrImportTest, PlannerWorldsWithKeyValuePairsAndNoTypeCodes) {
  Graph g(ReplicaId{1, 1});
  auto r = import_dsr_file(g, fixture("dsr/planner_untyped.json"));
  ASSERT_TRUE(r.ok()) << r.error().message;
  // No names: <type>_<id>. {"key": "alias", "value": "package1"} is the attribute alias.
  EXPECT_EQ(attr(g, "obj_1", "alias"), Value("package1"));
  EXPECT_EQ(attr(g, "obj_1", "pos_x"), Value::int32(0));
  EXPECT_EQ(attr(g, "obj_1", "pos_y"), Value(-150.5));
  EXPECT_EQ(attr(g, "lctn_8", "alias"), Value("PGH-PO"));
  EXPECT_TRUE(g.has_edge(node(g, "obj_1"), node(g, "lctn_8"), "at"));
}

TEST(DsrImportTest, CortexQuirksImportWithWarningsOrAreRefusedWhenStrict) {
  Graph g(ReplicaId{1, 1});
  auto r = import_dsr_file(g, fixture("dsr/cortex_quirks.json"));
  ASSERT_TRUE(r.ok()) << r.error().message;
  // A link to a missing symbol is skipped, as CORTEX does.
  EXPECT_TRUE(has_warning(r.value(), "/DSRModel/symbols/100/links/0: no symbol with id 999: the link 'has' is skipped"));
  EXPECT_EQ(r->edges, 0u);
  // An RT link without Euler angles (rt_quaternion only, which CORTEX's RT API does not read).
  EXPECT_TRUE(has_warning(r.value(), "has \"rt_translation\" but no \"rt_rotation_euler_xyz\": taken as 0"));
  EXPECT_EQ(attr(g, "room", "height"), Value::int32(5011));  // rounded, as Qt's toInt() does
  EXPECT_TRUE(has_warning(r.value(), "5010.7 is not an integer: rounded to 5011"));
  EXPECT_EQ(attr(g, "room_200", "rt:rt_quaternion"), Value(graph::FloatVec{0, 0, 0, 1}));
  EXPECT_NEAR(g.rt_edge(node(g, "room_200"))->pose.translation[0], 7.0, 1e-15);
  // Names: a second "room" gets its id; '~' becomes '-'; no name: <type>_<id>.
  EXPECT_TRUE(has_warning(r.value(), "the name 'room' is taken by an earlier symbol: named 'room_200'"));
  EXPECT_TRUE(g.find_node("a-b").has_value());
  EXPECT_TRUE(g.find_node("person_400").has_value());
  // --strict refuses the file whole.
  Graph h(ReplicaId{1, 1});
  ImportOptions strict;
  strict.strict = true;
  auto refused = import_dsr_file(h, fixture("dsr/cortex_quirks.json"), strict);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.error().code, ErrorCode::kRefused);
  EXPECT_EQ(h.node_count(), 0u);
}

TEST(DsrImportTest, MalformedFilesNameTheFileAndTheElement) {
  auto error = [](const std::string& name) { return file_refusal(import_dsr, "malformed/" + name); };
  const std::string dir = fixture("malformed/");
  EXPECT_EQ(error("dsr_bad_code.json"),
            dir + "dsr_bad_code.json:/DSRModel/symbols/12/attribute/pos: type code 3 expects an array of numbers");
  EXPECT_EQ(error("dsr_syntax.json").rfind(dir + "dsr_syntax.json:2:", 0), 0u) << error("dsr_syntax.json");
  EXPECT_NE(error("dsr_syntax.json").find("JSON syntax error"), std::string::npos);
  EXPECT_NE(error("dsr_two_parents.json").find("/DSRModel/symbols/2/links/0: symbol 3 already has an RT parent (symbol 1"),
            std::string::npos)
      << error("dsr_two_parents.json");
  EXPECT_NE(error("dsr_cycle.json").find("the RT links form a cycle"), std::string::npos);
  EXPECT_NE(error("dsr_pack_mismatch.json").find("rt_timestamps: expected one time stamp per sample (2)"),
            std::string::npos)
      << error("dsr_pack_mismatch.json");
}

TEST(DsrImportTest, OtherMistakes) {
  const std::string world = R"({"DSRModel": {"symbols": {"1": {"id": "1", "name": "w", "type": "world", )";
  EXPECT_EQ(dsr_error_of(world + R"("attribute": {"x": {"type": 14, "value": 1}}}}}})"),
            "dsr.json:/DSRModel/symbols/1/attribute/x: unknown type code 14 (CORTEX's codes are 0 to 13)");
  EXPECT_EQ(dsr_error_of(world + R"("attribute": {"x": {"type": 1, "value": 3000000000}}}}}})"),
            "dsr.json:/DSRModel/symbols/1/attribute/x: type code 1 expects an integer in int32 range");
  EXPECT_EQ(dsr_error_of(world + R"("attribute": {"x": {"type": 11, "value": [1, 2]}}}}}})"),
            "dsr.json:/DSRModel/symbols/1/attribute/x: type code 11 expects an array of 3 numbers");
  EXPECT_EQ(dsr_error_of(world + R"("attribute": {"dsr_id": {"type": 7, "value": 5}}}}}})"),
            "dsr.json:/DSRModel/symbols/1/attribute/dsr_id: \"dsr_id\" is where Quiver keeps the CORTEX id: a file "
            "cannot set it");
  EXPECT_EQ(dsr_error_of(world + R"("links": [{"src": "1", "dst": "1", "label": "RT"}]}}}})"),
            "dsr.json:/DSRModel/symbols/1/links/0: an RT link from a symbol to itself (a frame is not its own parent)");
  EXPECT_EQ(dsr_error_of(R"({"DSRModel": {"symbols": {"1": {"id": "x1", "type": "t"}}}})"),
            "dsr.json:/DSRModel/symbols/1/id: expected a CORTEX id (an unsigned integer)");
  EXPECT_EQ(dsr_error_of(R"({"DSRModel": {"symbols": [{"id": "1", "type": "t"}, {"id": "1", "type": "u"}]}})"),
            "dsr.json:/DSRModel/symbols/1: a second symbol with id 1");
  EXPECT_EQ(dsr_error_of(R"({"robots": []})"), "dsr.json:/: not a CORTEX DSR world: no \"DSRModel\" object at the top");
  // A child's own attribute named as its RT link's pose key could not be exported back (the
  // pose goes there): refused, not lost on the way out. Under no RT link it is an attribute.
  const std::string rt_child = R"({"DSRModel": {"symbols": {"1": {"id": "1", "name": "w", "type": "world", "links": [
      {"src": "1", "dst": "2", "label": "RT"}]}, "2": {"id": "2", "name": "c", "type": "t", "attribute": {)";
  EXPECT_EQ(dsr_error_of(rt_child + R"("rt:rt_translation": {"type": 3, "value": [1, 2, 3]}}}}}})"),
            "dsr.json:/DSRModel/symbols/2: the attribute 'rt:rt_translation' names the pose key 'rt_translation' of "
            "the RT link from symbol 1 (attributes prefixed rt: are that link's): it could not be written back; "
            "rename it");
  EXPECT_EQ(acceptance(import_dsr, rt_child + R"("rt:calibrated": {"type": 4, "value": true}}}}}})", "d.json"), "");
  EXPECT_EQ(acceptance(import_dsr, world + R"("attribute": {"rt:rt_translation": {"type": 3, "value": [1, 2, 3]}}}}}})", "d.json"), "");
}

TEST(DsrImportTest, AFileForAnotherCommandSaysSo) {
  EXPECT_EQ(dsr_error_of("<?xml version=\"1.0\"?>\n<AGMModel>\n</AGMModel>\n", "w.xml"),
            "w.xml: this is an AGM XML world (root <AGMModel>); use quiver import-agm");
  EXPECT_EQ(dsr_error_of(R"({"quiver_world": 1, "nodes": []})", "q.json"),
            "q.json: this is a Quiver world file (\"quiver_world\"): it needs no import; use it as it is (quiver agent "
            "--world, quiver lookup, quiver render...)");
  EXPECT_EQ(dsr_error_of("<robot name=\"r\"><link name=\"a\"/></robot>", "r.urdf"),
            "r.urdf: this is XML (root <robot>), not a CORTEX DSR JSON world; a URDF robot: use quiver import-urdf");
}

TEST(DsrImportTest, ARefusedFileLeavesTheGraphAsItWas) {
  Graph g(ReplicaId{1, 1});
  {
    auto tx = g.begin();
    ASSERT_TRUE(tx.create_node("world", "mug").ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  const auto before = g.digest();
  // current_layout.json has a node "mug": the name is taken in this graph.
  auto r = import_dsr_file(g, fixture("dsr/current_layout.json"));
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, ErrorCode::kAlreadyExists);
  EXPECT_NE(r.error().message.find("/DSRModel/symbols/5: the graph already has a node named 'mug'"), std::string::npos)
      << r.error().message;
  EXPECT_EQ(g.digest(), before);
  // A late error (the cycle is found after every symbol and link was read) changes nothing either.
  ASSERT_FALSE(import_dsr_file(g, fixture("malformed/dsr_cycle.json")).ok());
  EXPECT_EQ(g.digest(), before);
}

}  // namespace
}  // namespace quiver::interop
