// Missions (AGM's .aggt targets): parsing, and telling whether a world holds one and what is
// missing. Fixtures: tests/agents/rules/planner/fixtures (a warehouse domain written for these tests).

#include <gtest/gtest.h>

#include "quiver/agents/rules/grammar/grammar.h"
#include "quiver/agents/rules/mission/mission.h"
#include "quiver/interop/agm.h"

namespace quiver::agents {
namespace {

const std::string kDir = std::string(QUIVER_PLANNER_FIXTURES) + "/";

Mission parse(const std::string& text) {
  auto m = parse_mission(text, "m.aggt");
  EXPECT_TRUE(m.ok()) << m.error().to_string();
  return m.ok() ? *m : Mission{};
}

struct Warehouse {
  graph::Graph g{graph::ReplicaId{7, 1}};
  Grammar grammar;
  Warehouse() {
    auto r = interop::import_agm_file(g, kDir + "warehouse.xml");
    EXPECT_TRUE(r.ok()) << r.error().to_string();
    auto gr = load_grammar_file(kDir + "warehouse.aggl");
    EXPECT_TRUE(gr.ok()) << gr.error().to_string();
    grammar = *gr;
  }
  MissionReport check(const std::string& text) { return check_mission(parse(text), g, grammar.types); }
  void link(const char* a, const char* b, const char* label) {
    auto tx = g.begin();
    ASSERT_TRUE(tx.insert_edge(*g.find_node(a), *g.find_node(b), label).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
};

bool mentions(const MissionReport& r, const std::string& what) {
  for (const std::string& m : r.missing)
    if (m.find(what) != std::string::npos) return true;
  return false;
}

TEST(MissionParseTest, ReadsConstantsVariablesNegatedLinksPositionsAndTheFormula) {
  Mission m = parse(R"(
{
	1:robot(1,1)
	20:table
	obj:object(-10,20)
	1->20(know)
	obj->20(in)
	3->1(block)*
	3:person(0,0)
}
precondition
{
	(forall o:object (when (in o 20) (= o obj)))
}
)");
  ASSERT_EQ(m.pattern.nodes.size(), 4u);
  EXPECT_TRUE(m.is_constant("1"));
  EXPECT_TRUE(m.is_constant("20"));
  EXPECT_TRUE(m.is_constant("3"));
  EXPECT_FALSE(m.is_constant("obj"));
  EXPECT_EQ(m.pattern.node("obj")->type, "object");
  ASSERT_TRUE(m.pattern.node("obj")->pos.has_value());
  EXPECT_EQ(m.pattern.node("obj")->pos->first, -10);
  EXPECT_FALSE(m.pattern.node("20")->pos.has_value());
  ASSERT_EQ(m.pattern.edges.size(), 3u);
  EXPECT_FALSE(m.pattern.edges[0].negated);
  EXPECT_TRUE(m.pattern.edges[2].negated);
  EXPECT_EQ(m.pattern.edges[2].label, "block");
  ASSERT_TRUE(m.formula.has_value());
  EXPECT_EQ(m.formula->kind, Formula::Kind::kForall);
}

TEST(MissionParseTest, EmptyPartsAreAllowed) {
  EXPECT_TRUE(parse("").pattern.nodes.empty());
  Mission m = parse("{ 1:robot }\nprecondition { }");
  EXPECT_EQ(m.pattern.nodes.size(), 1u);
  EXPECT_FALSE(m.formula.has_value());
}

TEST(MissionParseTest, ErrorsNameFileLineColumnAndWhatWasWrong) {
  auto bad = [](const std::string& text) {
    auto m = parse_mission(text, "t.aggt");
    EXPECT_FALSE(m.ok()) << text;
    return m.ok() ? std::string() : m.error().message;
  };
  EXPECT_EQ(bad("{\n  1:robot\n  1->2(in)\n}"), "t.aggt:3:3: link uses undeclared node '2' in the target");
  EXPECT_EQ(bad("{\n  1:robot 1:room\n}"), "t.aggt:2:11: node '1' is declared twice in the target");
  EXPECT_NE(bad("{ 1:robot 1->1(in }").find("t.aggt:1:19: expected ')' to close the link label"), std::string::npos);
  EXPECT_NE(bad("{ 1:robot }\nprecondition { (in 1 x) }").find("t.aggt:2:"), std::string::npos);
  EXPECT_NE(bad("{ 1:robot } garbage").find("t.aggt:1:13: expected the end of the mission"), std::string::npos);
  EXPECT_NE(bad("{ 1:robot").find("t.aggt:1:10"), std::string::npos);
}

TEST(MissionParseTest, TextAfterTheFormulaIsIgnoredWithANoteAsAgmDoes) {
  Mission m = parse("{ 1:robot }\nprecondition { (not (busy 1 1)) ) }");
  ASSERT_EQ(m.notes.size(), 1u);
  EXPECT_NE(m.notes[0].find("m.aggt:2:33"), std::string::npos) << m.notes[0];
}

TEST(MissionCheckTest, HoldsOrSaysWhichLinkIsMissing) {
  Warehouse w;
  MissionReport yes = w.check("{ 1:robot 10:room 1->10(in) }");
  EXPECT_TRUE(yes.holds);
  EXPECT_TRUE(yes.missing.empty());
  MissionReport no = w.check("{ 1:robot 12:room 1->12(in) }");
  EXPECT_FALSE(no.holds);
  ASSERT_EQ(no.missing.size(), 1u);
  EXPECT_EQ(no.missing[0], "link 1->12(in): 1 (robot) -[in]-> 12 (office) is missing");
  EXPECT_EQ(no.satisfied, 2);
  EXPECT_EQ(no.total, 3);
  w.link("robot", "office", "in");
  EXPECT_TRUE(w.check("{ 1:robot 12:room 1->12(in) }").holds);
}

TEST(MissionCheckTest, VariablesMatchSubtypesInjectively) {
  Warehouse w;
  // The box and the parcel are objects (the domain's types): two distinct objects exist.
  MissionReport r = w.check("{ a:object b:object 12:room a->12(at) }");
  EXPECT_TRUE(r.holds);
  // Without the domain's types a box is not an object.
  MissionReport untyped = check_mission(parse("{ a:object 12:room a->12(at) }"), w.g);
  EXPECT_FALSE(untyped.holds);
  EXPECT_TRUE(mentions(untyped, "node a:object: no object fits")) << untyped.missing[0];
  // Two variables never match one node.
  MissionReport one = w.check("{ a:box b:box }");
  EXPECT_FALSE(one.holds);
  EXPECT_TRUE(mentions(one, "no box fits"));
}

TEST(MissionCheckTest, NegatedLinksAndAbsentConstantsAreReported) {
  Warehouse w;
  MissionReport r = w.check("{ 30:box 30->30(full)* }");
  EXPECT_FALSE(r.holds);
  EXPECT_TRUE(mentions(r, "link 30->30(full)*: 30 (box) -[full]-> 30 (box) exists and must not"));
  MissionReport gone = w.check("{ 99:room 1:robot 1->99(in) }");
  EXPECT_FALSE(gone.holds);
  EXPECT_TRUE(mentions(gone, "node 99:room: the world has no node with that id"));
  MissionReport wrong = w.check("{ 10:robot }");
  EXPECT_FALSE(wrong.holds);
  EXPECT_TRUE(mentions(wrong, "node 10:robot: node 10 (hall) is a room"));
}

TEST(MissionCheckTest, TheFormulaDecidesWhenTheGraphMatches) {
  Warehouse w;
  const char* nobody_holds = "{ 1:robot }\nprecondition { (not (exists o:object (holds 1 o))) }";
  EXPECT_TRUE(w.check(nobody_holds).holds);
  w.link("robot", "thing", "holds");
  MissionReport r = w.check(nobody_holds);
  EXPECT_FALSE(r.holds);
  ASSERT_EQ(r.missing.size(), 1u);
  EXPECT_NE(r.missing[0].find("the precondition formula is false"), std::string::npos);
  // forall/when: every object in the store is the variable's node.
  EXPECT_TRUE(w.check("{ x:object 11:room x->11(at) }\nprecondition { (forall o:object (when (at o 11) (= o x))) }")
                  .holds);
  w.link("parcel", "store", "at");
  EXPECT_FALSE(w.check("{ x:object 11:room x->11(at) }\nprecondition { (forall o:object (when (at o 11) (= o x))) }")
                   .holds);
}

// AGM's planner examples state targets as <AGMModel> patterns (AGM's
// AGGLPlanner/example_HRI/clean_table_easy/target0.xml has <symbol id="tazaR" type="object"/>): a
// numeric id is a world node, any other a variable, and enabled="false" negates a link.
TEST(MissionXmlTargetTest, AgmModelTargetsAreMissions) {
  auto m = parse_mission(
      "<AGMModel>\n"
      "  <symbol id=\"01\" type=\"robot\" x=\"-235\" y=\"+150\"/>\n"
      "  <symbol id=\"obj\" type=\"object\"/> <symbol id=\"12\" type=\"room\"/>\n"
      "  <link src=\"obj\" dst=\"12\" label=\"at\"/>\n"
      "  <link src=\"1\" dst=\"12\" label=\"in\" enabled=\"False\"/>\n"
      "</AGMModel>\n<!-- a comment after the model, as AGM's grasp/target1.xml has -->\n",
      "target.xml");
  ASSERT_TRUE(m.ok()) << m.error().to_string();
  ASSERT_EQ(m->pattern.nodes.size(), 3u);
  EXPECT_EQ(m->pattern.nodes[0].var, "1");  // "01" is AGM id 1
  EXPECT_TRUE(m->is_constant("1"));
  EXPECT_FALSE(m->is_constant("obj"));
  EXPECT_EQ(m->pattern.nodes[0].pos, std::make_optional(std::make_pair(-235, 150)));
  EXPECT_EQ(m->pattern.nodes[1].loc.line, 3);
  ASSERT_EQ(m->pattern.edges.size(), 2u);
  EXPECT_FALSE(m->pattern.edges[0].negated);
  EXPECT_TRUE(m->pattern.edges[1].negated);
  // It is checked as the same .aggt would be.
  Warehouse w;
  MissionReport r = check_mission(*m, w.g, w.grammar.types);
  EXPECT_TRUE(r.holds);  // the box is at the office, and the robot is not there
  w.link("robot", "office", "in");
  r = check_mission(*m, w.g, w.grammar.types);
  EXPECT_FALSE(r.holds);
  EXPECT_TRUE(mentions(r, "link 1->12(in)*: 1 (robot) -[in]-> 12 (office) exists and must not")) << r.missing[0];
}

TEST(MissionXmlTargetTest, MistakesAndFilesOfAnotherKindAreNamed) {
  auto error = [](const std::string& text) {
    auto m = parse_mission(text, "t.xml");
    return m.ok() ? std::string("accepted") : m.error().message;
  };
  EXPECT_EQ(error("<AGMModel>\n<symbol type=\"robot\"/>\n</AGMModel>"), "t.xml:2:1: <symbol> without id");
  EXPECT_EQ(error("<AGMModel><symbol id=\"a\" type=\"t\"/><link src=\"a\" dst=\"b\" label=\"x\"/></AGMModel>"),
            "t.xml:1:36: the link names symbol b, which no <symbol> before it declares");
  EXPECT_EQ(error("<AGMModel><symbol id=\"5\" type=\"t\"/><symbol id=\"05\" type=\"u\"/></AGMModel>"),
            "t.xml:1:36: a second symbol with id 5");
  EXPECT_EQ(error("<?xml version=\"1.0\"?>\n<robot name=\"r\"/>"),
            "t.xml:2:1: the root element is <robot>: not a mission (a mission is an AGM target: a .aggt file, or an "
            "AGM XML target with the root <AGMModel>)");
  EXPECT_EQ(error("{\"quiver_world\": 1, \"nodes\": []}"),
            "t.xml: this is JSON (a world file?), not a mission (a mission is an AGM target: a .aggt file, or an AGM "
            "XML target with the root <AGMModel>)");
  EXPECT_EQ(error("name=HRI\n===\nr : active(1)\n{ { a:t } => { a:t } }").substr(0, 65),
            "t.xml: this is a grammar (.aggl: a domain's rules), not a mission");
  // Quiver's grammars begin with comment lines (agents/apps/agm/grammars/*.aggl).
  EXPECT_EQ(error("# Clean the table.\n\n// rules below\ngrammar cleanTable\ntypes {\n  robot\n}\n").substr(0, 65),
            "t.xml: this is a grammar (.aggl: a domain's rules), not a mission");
  EXPECT_NE(error("<AGMModel><symbol").find("t.xml:1:"), std::string::npos);
  EXPECT_NE(error("<AGMModel><symbol").find("XML syntax error"), std::string::npos);
  // What a target does not match is noted, not refused.
  auto noted = parse_mission("<AGMModel><symbol id=\"1\" type=\"t\"><attribute key=\"k\" value=\"v\"/></symbol>"
                             "<comment/></AGMModel>",
                             "t.xml");
  ASSERT_TRUE(noted.ok());
  ASSERT_EQ(noted->notes.size(), 2u);
  EXPECT_NE(noted->notes[0].find("symbol 1: attributes are not part of a target"), std::string::npos);
  EXPECT_NE(noted->notes[1].find("<comment> is not part of an AGM target: ignored"), std::string::npos);
}

TEST(MissionCheckTest, FixtureFilesLoad) {
  for (const char* f : {"parcel_to_hall.aggt", "robot_in_office.aggt", "ball_in_hall.aggt", "two_parcels.aggt"}) {
    auto m = load_mission_file(kDir + f);
    EXPECT_TRUE(m.ok()) << f << ": " << m.error().to_string();
  }
  auto missing = load_mission_file(kDir + "no_such.aggt");
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error().code, ErrorCode::kIo);
}

}  // namespace
}  // namespace quiver::agents
