#include "quiver/agents/rules/grammar/grammar.h"

#include <gtest/gtest.h>

#include "quiver/agents/rules/grammar/grammar_guard.h"
#include "quiver/graph/codec.h"

namespace quiver::agents {
namespace {

using graph::Graph;
using graph::NodeId;
using graph::ReplicaId;
using graph::Symbol;
using graph::Value;

Grammar load(const char* file) {
  auto g = load_grammar_file(std::string(QUIVER_GRAMMARS) + "/" + file);
  EXPECT_TRUE(g.ok()) << g.error().to_string();
  return g.ok() ? *g : Grammar{};
}

// A replica whose every commit is checked against a grammar; counts what it publishes.
struct Checked {
  explicit Checked(const char* grammar, std::uint64_t agent = 1) : g(ReplicaId{agent, 1}), checker(load(grammar)) {
    check_commits();
    g.set_delta_sink([this](const graph::GraphDelta& d) { published.push_back(graph::encode(d)); });
  }
  // (Re)installs the grammar check on every commit, e.g. after building a world without it.
  void check_commits() {
    g.set_commit_validator([this](const Graph& graph, const std::vector<graph::TxnOp>& ops) {
      return checker.check(graph, ops, &last);
    });
  }
  Graph g;
  GrammarChecker checker;
  RuleMatch last;
  std::vector<std::vector<std::uint8_t>> published;

  NodeId id(const char* name) { return *g.find_node(name); }
  Status edge_swap(const char* from, const char* to, const char* old_label, const char* new_label) {
    auto tx = g.begin();
    EXPECT_TRUE(tx.delete_edge(id(from), id(to), Symbol(old_label)).ok());
    EXPECT_TRUE(tx.insert_edge(id(from), id(to), Symbol(new_label)).ok());
    auto r = tx.commit();
    return r.ok() ? Status{} : Status(r.error());
  }
};

// The DSR of the Barthel test around the Speech agent, created without a grammar.
void barthel_world(Graph& g) {
  auto tx = g.begin();
  NodeId robot = *tx.create_node("robot", "robot");
  NodeId speaking = *tx.create_node("speaking", "speaking");
  NodeId person = *tx.create_node("person", "person");
  NodeId answer = *tx.create_node("answer", "answer");
  NodeId test = *tx.create_node("test", "test");
  NodeId part = *tx.create_node("test_part", "test_part");
  ASSERT_TRUE(tx.insert_edge(robot, speaking, Symbol("is_not")).ok());
  ASSERT_TRUE(tx.insert_edge(person, answer, Symbol("can")).ok());
  ASSERT_TRUE(tx.insert_edge(test, part, Symbol("is_in"), {{Symbol("label"), Value("How do you feel?")}}).ok());
  ASSERT_TRUE(tx.commit().ok());
}

TEST(GrammarTest, SpeechLegalSequenceIsAccepted) {
  Checked s("speech.aggl");
  s.g.set_commit_validator(nullptr);
  barthel_world(s.g);
  s.check_commits();
  ASSERT_TRUE(s.edge_swap("robot", "speaking", "is_not", "is").ok());
  EXPECT_EQ(s.last.rule, "startSpeaking");
  ASSERT_TRUE(s.edge_swap("robot", "speaking", "is", "finish").ok());
  EXPECT_EQ(s.last.rule, "finishSpeaking");
  ASSERT_TRUE(s.edge_swap("person", "answer", "can", "waiting").ok());
  ASSERT_TRUE(s.edge_swap("person", "answer", "waiting", "got").ok());
  EXPECT_EQ(s.last.rule, "setAnswer");
  // Attribute updates need no rule ('allow attributes').
  auto tx = s.g.begin();
  ASSERT_TRUE(tx.set(s.id("person"), "answer_text", Value("fine")).ok());
  EXPECT_TRUE(tx.commit().ok());
}

TEST(GrammarTest, IllegalJumpIsRefusedAndPublishesNothing) {
  Checked s("speech.aggl");
  s.g.set_commit_validator(nullptr);
  barthel_world(s.g);
  s.check_commits();
  const std::size_t before = s.published.size();
  const auto digest = s.g.digest();
  Status st = s.edge_swap("robot", "speaking", "is_not", "finish");
  ASSERT_FALSE(st.ok());
  EXPECT_EQ(st.error().code, ErrorCode::kRefused);
  EXPECT_NE(st.error().message.find("closest rule"), std::string::npos) << st.error().message;
  EXPECT_NE(st.error().message.find("robot -[is_not]-> speaking"), std::string::npos) << st.error().message;
  EXPECT_EQ(s.published.size(), before) << "nothing is published";
  EXPECT_EQ(s.g.digest(), digest) << "nothing changes";
  EXPECT_TRUE(s.g.has_edge(s.id("robot"), s.id("speaking"), Symbol("is_not")));
  // Waiting for an answer the person cannot give yet is refused too, naming why.
  Status st2 = s.edge_swap("person", "answer", "can", "got");
  ASSERT_FALSE(st2.ok());
  EXPECT_NE(st2.error().message.find("closest rule"), std::string::npos) << st2.error().message;
}

TEST(GrammarTest, PreconditionOnAnEdgeLabel) {
  Checked s("speech.aggl");
  s.g.set_commit_validator(nullptr);
  barthel_world(s.g);
  {  // clear the sentence: nothing to say
    auto tx = s.g.begin();
    ASSERT_TRUE(tx.set_edge_attr(graph::EdgeKey{s.id("test"), s.id("test_part"), Symbol("is_in")}, Symbol("label"),
                                 Value(""))
                    .ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  s.check_commits();
  Status st = s.edge_swap("robot", "speaking", "is_not", "is");
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.error().message.find("precondition"), std::string::npos) << st.error().message;
}

struct AgmWorld {
  Checked s{"agm.aggl"};
  NodeId robot, kitchen, hall, bedroom, mug, cup;
  AgmWorld() {
    s.g.set_commit_validator(nullptr);
    auto tx = s.g.begin();
    robot = *tx.create_node("robot", "robot");
    kitchen = *tx.create_node("room", "kitchen");
    hall = *tx.create_node("room", "hall");
    bedroom = *tx.create_node("room", "bedroom");
    mug = *tx.create_node("mug", "mug");
    cup = *tx.create_node("object", "cup");
    EXPECT_TRUE(tx.insert_edge(robot, kitchen, Symbol("in")).ok());
    EXPECT_TRUE(tx.insert_edge(kitchen, hall, Symbol("transitable")).ok());
    EXPECT_TRUE(tx.insert_edge(mug, kitchen, Symbol("in")).ok());
    EXPECT_TRUE(tx.insert_edge(cup, kitchen, Symbol("in")).ok());
    EXPECT_TRUE(tx.insert_edge(robot, mug, Symbol("reach")).ok());
    EXPECT_TRUE(tx.insert_edge(robot, cup, Symbol("noReach")).ok());
    EXPECT_TRUE(tx.commit().ok());
    s.check_commits();
  }
  Status move(NodeId from, NodeId to, bool with_mug) {
    auto tx = s.g.begin();
    EXPECT_TRUE(tx.delete_edge(robot, from, Symbol("in")).ok());
    EXPECT_TRUE(tx.insert_edge(robot, to, Symbol("in")).ok());
    if (with_mug) {
      EXPECT_TRUE(tx.delete_edge(mug, from, Symbol("in")).ok());
      EXPECT_TRUE(tx.insert_edge(mug, to, Symbol("in")).ok());
    }
    auto r = tx.commit();
    return r.ok() ? Status{} : Status(r.error());
  }
  Status grasp(NodeId o) {
    auto tx = s.g.begin();
    EXPECT_TRUE(tx.insert_edge(robot, o, Symbol("carrying")).ok());
    auto r = tx.commit();
    return r.ok() ? Status{} : Status(r.error());
  }
};

TEST(GrammarTest, ChangeRoomNeedsATransitableEdge) {
  AgmWorld w;
  Status st = w.move(w.kitchen, w.bedroom, false);
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.error().message.find("transitable"), std::string::npos) << st.error().message;
  ASSERT_TRUE(w.move(w.kitchen, w.hall, false).ok()) << "nothing carried: the robot alone moves";
  EXPECT_EQ(w.s.last.rule, "changeRoom");
}

TEST(GrammarTest, CarriedObjectsMoveRoomsWithTheRobot) {
  AgmWorld w;
  ASSERT_TRUE(w.grasp(w.mug).ok());
  EXPECT_EQ(w.s.last.rule, "grasp");
  Status alone = w.move(w.kitchen, w.hall, false);
  ASSERT_FALSE(alone.ok()) << "leaving the carried mug behind is not a changeRoom";
  EXPECT_NE(alone.error().message.find("forall"), std::string::npos) << alone.error().message;
  ASSERT_TRUE(w.move(w.kitchen, w.hall, true).ok()) << w.s.last.rule;
  EXPECT_TRUE(w.s.g.has_edge(w.mug, w.hall, Symbol("in")));
}

TEST(GrammarTest, GraspingNeedsReachAndFreeHands) {
  AgmWorld w;
  Status far = w.grasp(w.cup);
  ASSERT_FALSE(far.ok()) << "noReach";
  ASSERT_TRUE(w.grasp(w.mug).ok());
  {  // the cup comes within reach (a passive rule)
    auto tx = w.s.g.begin();
    ASSERT_TRUE(tx.delete_edge(w.robot, w.cup, Symbol("noReach")).ok());
    ASSERT_TRUE(tx.insert_edge(w.robot, w.cup, Symbol("reach")).ok());
    ASSERT_TRUE(tx.commit().ok());
    EXPECT_EQ(w.s.last.rule, "seeReach");
  }
  Status full = w.grasp(w.cup);
  ASSERT_FALSE(full.ok()) << "already carrying the mug";
  EXPECT_NE(full.error().message.find("precondition"), std::string::npos) << full.error().message;
}

TEST(GrammarTest, ClaimedMatchesVerifyCheaply) {
  AgmWorld w;
  auto tx = w.s.g.begin();
  ASSERT_TRUE(tx.delete_edge(w.robot, w.kitchen, Symbol("in")).ok());
  ASSERT_TRUE(tx.insert_edge(w.robot, w.hall, Symbol("in")).ok());
  RuleMatch m;
  ASSERT_TRUE(w.s.checker.check(w.s.g, tx.ops(), &m).ok());
  EXPECT_TRUE(w.s.checker.verify(w.s.g, tx.ops(), m).ok());
  RuleMatch lie = m;
  for (auto& [var, id] : lie.binding)
    if (var == "b") id = w.bedroom;
  EXPECT_FALSE(w.s.checker.verify(w.s.g, tx.ops(), lie).ok()) << "a wrong binding does not verify";
  lie.rule = "grasp";
  EXPECT_FALSE(w.s.checker.verify(w.s.g, tx.ops(), lie).ok());
}

TEST(GrammarTest, ConcurrentValidMovesMergeIntoAForbiddenStateSeenAlikeEverywhere) {
  // Two agents move the robot out of the kitchen at once, to different rooms: each change is
  // a valid changeRoom, their merge puts the robot in two rooms.
  AgmWorld a;
  Graph b(ReplicaId{2, 1});
  GrammarChecker bcheck(load("agm.aggl"));
  std::vector<std::vector<std::uint8_t>> from_b;
  b.set_delta_sink([&](const graph::GraphDelta& d) { from_b.push_back(graph::encode(d)); });
  for (const auto& m : a.s.published) b.merge(*graph::decode(m));
  {  // both rooms are transitable from the kitchen
    a.s.g.set_commit_validator(nullptr);
    auto tx = a.s.g.begin();
    ASSERT_TRUE(tx.insert_edge(a.kitchen, a.bedroom, Symbol("transitable")).ok());
    ASSERT_TRUE(tx.commit().ok());
    b.merge(*graph::decode(a.s.published.back()));
    a.s.check_commits();
  }
  ASSERT_TRUE(a.move(a.kitchen, a.hall, false).ok());
  b.set_commit_validator([&](const Graph& graph, const auto& ops) { return bcheck.check(graph, ops); });
  {
    auto tx = b.begin();
    ASSERT_TRUE(tx.delete_edge(a.robot, a.kitchen, Symbol("in")).ok());
    ASSERT_TRUE(tx.insert_edge(a.robot, a.bedroom, Symbol("in")).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  EXPECT_TRUE(a.s.checker.all_violations(a.s.g).empty());
  a.s.g.merge(*graph::decode(from_b.back()));
  b.merge(*graph::decode(a.s.published.back()));
  auto va = a.s.checker.violations_around(a.s.g, {a.robot});
  auto vb = bcheck.violations_around(b, {a.hall, a.bedroom});
  ASSERT_EQ(va.size(), 1u);
  EXPECT_EQ(va, vb) << "the same violation, whichever node each replica started from";
  EXPECT_EQ(va[0].constraint, "robotInOneRoom");
  EXPECT_EQ(va, a.s.checker.all_violations(a.s.g));
}

// Unary predicates (self-loops) match with AGM's meaning: required, forbidden, set and cleared.
TEST(GrammarTest, UnaryPredicatesAreSelfLoopsInRules) {
  auto parsed = parse_grammar(R"(grammar unary
types { robot }
rule startMoving : active { { r:robot  !r->r(moving) } => { r:robot  r->r(moving) } }
rule stopMoving : active { { r:robot  r->r(moving) } => { r:robot } }
)");
  ASSERT_TRUE(parsed.ok()) << parsed.error().to_string();
  Graph g(ReplicaId{1, 1});
  NodeId robot;
  {
    auto tx = g.begin();
    robot = *tx.create_node("robot", "robot");
    ASSERT_TRUE(tx.commit().ok());
  }
  GrammarChecker checker(*parsed);
  RuleMatch m;
  g.set_commit_validator([&](const Graph& graph, const std::vector<graph::TxnOp>& ops) {
    return checker.check(graph, ops, &m);
  });
  auto change = [&](bool add) {
    auto tx = g.begin();
    Status op = add ? tx.insert_edge(robot, robot, Symbol("moving")) : tx.delete_edge(robot, robot, Symbol("moving"));
    if (!op.ok()) return op;
    auto r = tx.commit();
    return r.ok() ? Status{} : Status(r.error());
  };
  ASSERT_TRUE(change(true).ok());
  EXPECT_EQ(m.rule, "startMoving");
  EXPECT_TRUE(g.has_edge(robot, robot, Symbol("moving")));
  ASSERT_TRUE(change(false).ok());
  EXPECT_EQ(m.rule, "stopMoving");
  EXPECT_FALSE(change(false).ok()) << "clearing a predicate that does not hold";
  EXPECT_FALSE(g.has_edge(robot, robot, Symbol("moving")));
}

TEST(GrammarTest, ParseErrorsNameFileLineColumnAndWhatWasExpected) {
  struct Case {
    const char* text;
    const char* want;
  } cases[] = {
      {"types { robot }\nrule r : active {\n  { x:robot } => { x:robot y:ghost }\n}", "g.aggl:3:30: unknown type 'ghost'"},
      {"types { robot }\nrule r : sometimes { }", "g.aggl:2:10: expected 'active' or 'passive'"},
      {"types { robot }\nrule r : active {\n  { x:robot x->y(in) } => { x:robot }\n}", "g.aggl:3:13: edge uses undeclared variable 'y'"},
      {"types { a b : c }", "g.aggl:1:15: unknown base type 'c'"},
      {"allow everything", "g.aggl:1:7: expected 'attributes', 'rt-poses' or 'rt-moves'"},
      {"types { robot }\nrule r : active { { x:robot } => { x:robot } precondition { x.a == } }", "g.aggl:2:68: expected a string"},
      {"types { robot }\nrule r : active { { x:robot } }", "g.aggl:2:31: expected '=>'"},
  };
  for (const auto& c : cases) {
    auto g = parse_grammar(c.text, "g.aggl");
    ASSERT_FALSE(g.ok()) << c.text;
    EXPECT_EQ(g.error().code, ErrorCode::kMalformed);
    EXPECT_NE(g.error().message.find(c.want), std::string::npos) << "got: " << g.error().message;
  }
}

}  // namespace
}  // namespace quiver::agents

namespace quiver::agents {
namespace {

TEST(GrammarGuardTest, DeltasCarryTheirRuleAndReceiversVerifyIt) {
  // Agent a checks its commits with the guard; b verifies what arrives.
  graph::Graph a(ReplicaId{fnv1a64("speech"), 1}), b(ReplicaId{fnv1a64("panel"), 1});
  std::vector<std::vector<std::uint8_t>> wire;
  a.set_delta_sink([&](const graph::GraphDelta& d) { wire.push_back(graph::encode(d)); });
  barthel_world(a);
  for (const auto& m : wire) b.merge(*graph::decode(m));
  wire.clear();
  GrammarGuard ga(a, GrammarChecker(load("speech.aggl")), "speech");
  ga.install();
  GrammarGuard gb(b, GrammarChecker(load("speech.aggl")), "panel");
  std::vector<std::string> complaints;
  gb.on_unverified([&](const ReplicaId&, const Error& e) { complaints.push_back(e.message); });
  {
    auto tx = a.begin();
    ASSERT_TRUE(tx.delete_edge(*a.find_node("robot"), *a.find_node("speaking"), Symbol("is_not")).ok());
    ASSERT_TRUE(tx.insert_edge(*a.find_node("robot"), *a.find_node("speaking"), Symbol("is")).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  auto d = graph::decode(wire.back());
  ASSERT_TRUE(d.ok());
  EXPECT_EQ(d->rule, "startSpeaking") << "the claim travels with the delta";
  EXPECT_EQ(d->binding.size(), 4u);
  b.merge(*d);
  EXPECT_EQ(gb.deltas_verified(), 1u);
  EXPECT_TRUE(complaints.empty());

  // A rogue agent (no grammar of its own) jumps straight to 'finish' and lies about the rule.
  graph::Graph rogue(ReplicaId{fnv1a64("rogue"), 1});
  std::vector<std::vector<std::uint8_t>> rw;
  rogue.set_delta_sink([&](const graph::GraphDelta& x) { rw.push_back(graph::encode(x)); });
  rogue.merge(b.state());
  {
    auto tx = rogue.begin();
    ASSERT_TRUE(tx.delete_edge(*rogue.find_node("robot"), *rogue.find_node("speaking"), Symbol("is")).ok());
    ASSERT_TRUE(tx.insert_edge(*rogue.find_node("person"), *rogue.find_node("answer"), Symbol("got")).ok());
    (void)rogue.annotate_commit("finishSpeaking", {{"r", *rogue.find_node("robot")}, {"s", *rogue.find_node("speaking")}});
    ASSERT_TRUE(tx.commit().ok());
  }
  b.merge(*graph::decode(rw.back()));
  ASSERT_EQ(complaints.size(), 1u);
  EXPECT_NE(complaints[0].find("finishSpeaking"), std::string::npos) << complaints[0];
  {  // and a structural change that claims nothing
    auto tx = rogue.begin();
    ASSERT_TRUE(tx.delete_edge(*rogue.find_node("person"), *rogue.find_node("answer"), Symbol("got")).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  b.merge(*graph::decode(rw.back()));
  ASSERT_EQ(complaints.size(), 2u);
  EXPECT_NE(complaints[1].find("claims no rule"), std::string::npos) << complaints[1];
  EXPECT_EQ(gb.deltas_unverified(), 2u);
}

TEST(GrammarGuardTest, ConstraintsWhoseViolationsHaveTheSameBindingAreTrackedApart) {
  // Two constraints over the same variables, both broken by the same nodes.
  auto gr = parse_grammar(
      "types { robot room }\n"
      "constraint inTwoRooms { forbid { r:robot a:room b:room  r->a(in)  r->b(in) } }\n"
      "constraint nearTwoRooms { forbid { r:robot a:room b:room  r->a(near)  r->b(near) } }\n",
      "two.aggl");
  ASSERT_TRUE(gr.ok()) << gr.error().to_string();
  Graph g(ReplicaId{1, 1});
  GrammarGuard guard(g, GrammarChecker(std::move(*gr)), "observer");
  std::vector<std::string> seen;
  guard.on_violation([&](const Violation& v) { seen.push_back(v.constraint); });
  NodeId robot, kitchen, hall;
  {
    auto tx = g.begin();
    robot = *tx.create_node("robot", "robot");
    kitchen = *tx.create_node("room", "kitchen");
    hall = *tx.create_node("room", "hall");
    for (NodeId room : {kitchen, hall}) {
      ASSERT_TRUE(tx.insert_edge(robot, room, Symbol("in")).ok());
      ASSERT_TRUE(tx.insert_edge(robot, room, Symbol("near")).ok());
    }
    ASSERT_TRUE(tx.commit().ok());
  }
  EXPECT_EQ(seen, (std::vector<std::string>{"inTwoRooms", "nearTwoRooms"}));
  EXPECT_EQ(guard.open().size(), 2u);
  {  // one ends, the other stays open
    auto tx = g.begin();
    ASSERT_TRUE(tx.delete_edge(robot, hall, Symbol("near")).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  ASSERT_EQ(guard.open().size(), 1u);
  EXPECT_EQ(guard.open().begin()->first, "inTwoRooms");
  {  // and comes back: a new violation
    auto tx = g.begin();
    ASSERT_TRUE(tx.insert_edge(robot, hall, Symbol("near")).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  EXPECT_EQ(guard.violations_seen(), 3u);
  EXPECT_EQ(seen.back(), "nearTwoRooms");
}

TEST(GrammarGuardTest, AViolationPresentAtTheStartIsReportedWhenItsNodesChange) {
  // The world breaks a constraint before the guard starts: an attribute write to one of its
  // nodes is what first raises it, as does any change around it.
  Graph g(ReplicaId{1, 1});
  NodeId robot;
  {
    auto tx = g.begin();
    robot = *tx.create_node("robot", "robot");
    for (const char* room : {"kitchen", "hall"})
      ASSERT_TRUE(tx.insert_edge(robot, *tx.create_node("room", room), Symbol("in")).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  GrammarGuard guard(g, GrammarChecker(load("agm.aggl")), "observer");
  EXPECT_EQ(guard.violations_seen(), 0u);
  {
    auto tx = g.begin();
    ASSERT_TRUE(tx.set(robot, "battery", Value(0.5)).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  EXPECT_EQ(guard.violations_seen(), 1u);
  EXPECT_EQ(guard.open().size(), 1u);
}

}  // namespace
}  // namespace quiver::agents
