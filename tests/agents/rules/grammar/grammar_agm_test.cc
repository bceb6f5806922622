// AGM's dialect of AGGL (docs/grammar.md, "AGM's dialect"): the fixtures under grammars/agm/ are
// written as AGM's editor writes, and cover every construct; each is checked for what the parser
// makes of it and for the guard's verdicts with AGM's meaning.

#include <gtest/gtest.h>

#include "quiver/agents/rules/grammar/grammar.h"
#include "quiver/agents/rules/grammar/grammar_guard.h"
#include "quiver/agents/rules/grammar/retype.h"
#include "quiver/graph/codec.h"

namespace quiver::agents {
namespace {

using graph::Graph;
using graph::NodeId;
using graph::ReplicaId;
using graph::Symbol;

const std::string kDir = std::string(QUIVER_GRAMMARS) + "/agm/";

Grammar load(const std::string& file) {
  auto g = load_grammar_file(kDir + file);
  EXPECT_TRUE(g.ok()) << g.error().to_string();
  return g.ok() ? *g : Grammar{};
}

// A world under household.aggl: every commit after the set-up is checked.
struct World {
  Graph g{ReplicaId{1, 1}};
  GrammarChecker checker{load("household.aggl")};
  RuleMatch last;

  World() {}
  NodeId add(const char* type, const char* name) {
    auto tx = g.begin();
    NodeId id = *tx.create_node(type, name);
    EXPECT_TRUE(tx.commit().ok());
    return id;
  }
  void link(const char* from, const char* to, const char* label) {
    auto tx = g.begin();
    EXPECT_TRUE(tx.insert_edge(id(from), id(to), Symbol(label)).ok());
    EXPECT_TRUE(tx.commit().ok());
  }
  void check_from_now() {
    g.set_commit_validator([this](const Graph& graph, const std::vector<graph::TxnOp>& ops) {
      last = RuleMatch{};
      return checker.check(graph, ops, &last);
    });
  }
  NodeId id(const char* name) { return *g.find_node(name); }
  // Commits what `write` puts into one transaction.
  template <class Write>
  Status commit(const Write& write) {
    auto tx = g.begin();
    write(tx);
    auto r = tx.commit();
    return r.ok() ? Status{} : Status(r.error());
  }
  bool has(const char* from, const char* to, const char* label) {
    return g.has_edge(id(from), id(to), Symbol(label));
  }
  // Commits the edge changes: "-a b label" removes, "+a b label" adds.
  Status change(std::initializer_list<const char*> edits) {
    return commit([&](graph::Transaction& tx) {
      for (const char* e : edits) {
        char op;
        char a[64], b[64], l[64];
        EXPECT_EQ(std::sscanf(e, "%c%63s %63s %63s", &op, a, b, l), 4) << e;
        if (op == '+')
          EXPECT_TRUE(tx.insert_edge(id(a), id(b), Symbol(l)).ok()) << e;
        else
          EXPECT_TRUE(tx.delete_edge(id(a), id(b), Symbol(l)).ok()) << e;
      }
    });
  }
};

// ------------------------------------------------------------------ parsing

TEST(AgmGrammarTest, ReadsTheEditorFileWithItsHeaderTypesAndPositions) {
  const Grammar g = load("household.aggl");
  EXPECT_EQ(g.dialect, Grammar::Dialect::kAgm);
  EXPECT_EQ(g.name, "household");
  ASSERT_GE(g.properties.size(), 9u);
  EXPECT_EQ(g.properties[2], (std::pair<std::string, std::string>{"fontName", "Arial"}));
  // AGM's agents update attributes and poses outside the rules; moving an RT link is structural.
  EXPECT_TRUE(g.allow_attributes);
  EXPECT_TRUE(g.allow_rt_poses);
  EXPECT_FALSE(g.allow_rt_moves);
  // Inheritance, multiple too.
  EXPECT_TRUE(g.types.is_a("mug", "object"));
  EXPECT_TRUE(g.types.is_a("table", "object"));
  EXPECT_TRUE(g.types.is_a("tray", "container"));
  EXPECT_FALSE(g.types.is_a("object", "mug"));
  EXPECT_EQ(g.types.subtypes("container"),
            (std::vector<std::string>{"container", "table", "tray"}));
  // Positions are kept as metadata.
  const Rule* move = g.rule("changeRoom");
  ASSERT_NE(move, nullptr);
  EXPECT_TRUE(move->active);
  EXPECT_EQ(move->cost, 2);
  ASSERT_TRUE(move->lhs.node("a")->pos.has_value());
  EXPECT_EQ(*move->lhs.node("a")->pos, (std::pair<int, int>{-100, 0}));
  // '*' negates a link.
  const Rule* grasp = g.rule("grasp");
  ASSERT_EQ(grasp->lhs.edges.size(), 3u);
  EXPECT_FALSE(grasp->lhs.edges[0].negated);
  EXPECT_TRUE(grasp->lhs.edges[1].negated);
  EXPECT_EQ(grasp->lhs.edges[2].from, "r");  // a self-loop: a unary predicate
  EXPECT_EQ(grasp->lhs.edges[2].to, "r");
  // A variable typed differently on the two sides is retyped.
  const Rule* classify = g.rule("classify");
  EXPECT_FALSE(classify->active);
  EXPECT_EQ(classify->lhs.node("o")->type, "unknownObject");
  EXPECT_EQ(classify->rhs.node("o")->type, "knownObject");
  EXPECT_DOUBLE_EQ(g.rule("lookAround")->success, 0.8);
  EXPECT_DOUBLE_EQ(move->success, 1.0);
}

TEST(AgmGrammarTest, PreconditionsAndEffectsBecomeFormulasAndEffects) {
  const Grammar g = load("household.aggl");
  using K = Formula::Kind;
  const Formula& charge = *g.rule("startCharging")->precondition;
  ASSERT_EQ(charge.kind, K::kOr);
  EXPECT_EQ(charge.kids[0].kind, K::kEdge);
  EXPECT_EQ(charge.kids[0].edge.label, "low");
  const Formula& look = *g.rule("lookAround")->precondition;
  ASSERT_EQ(look.kind, K::kExists);
  EXPECT_FALSE(look.distinct) << "AGM's quantifiers range over every node of the type";
  EXPECT_EQ(look.vars[0].var, "p");
  EXPECT_EQ(look.vars[0].type, "person");
  // (forall p (when C F)) reads as forall p { C } => { F }; (= a b) compares nodes.
  const Formula& close = *g.rule("closeDoor")->precondition;
  ASSERT_EQ(close.kind, K::kAnd);
  ASSERT_EQ(close.kids[0].kind, K::kForall);
  EXPECT_EQ(close.kids[0].kids[0].kind, K::kEdge);
  EXPECT_EQ(close.kids[0].kids[1].kind, K::kSame);
  EXPECT_EQ(close.kids[1].kind, K::kNot);

  using E = Effect::Kind;
  const Effect& carry = *g.rule("changeRoom")->effect;
  ASSERT_EQ(carry.kind, E::kForall);
  EXPECT_EQ(carry.vars[0].type, "object");
  ASSERT_EQ(carry.kids[0].kind, E::kWhen);
  const Effect& moved = carry.kids[0].kids[0];
  ASSERT_EQ(moved.kind, E::kAll);
  EXPECT_EQ(moved.kids[0].kind, E::kRemoveEdge);
  EXPECT_EQ(moved.kids[1].kind, E::kAddEdge);
  const Effect& set = *g.rule("setTable")->effect;
  ASSERT_EQ(set.kind, E::kAll);
  EXPECT_EQ(set.kids[0].kind, E::kCreate);
  EXPECT_EQ(set.kids[0].type, "mug");
  EXPECT_EQ(set.kids[1].edge.from, "m") << "a created node is named in what follows";
  EXPECT_EQ(g.rule("clearTable")->effect->kids[0].kids[0].kind, E::kDelete);
  EXPECT_EQ(g.rule("recogniseAll")->effect->kids[0].kids[0].kind, E::kRetype);
}

TEST(AgmGrammarTest, HierarchicalDormantAndComboRulesAreFlagged) {
  const Grammar g = load("household.aggl");
  const Rule* serve = g.rule("serve");
  EXPECT_EQ(serve->kind, Rule::Kind::kHierarchical);
  EXPECT_EQ(serve->activates, (std::vector<std::string>{"fetch", "handOver"}));
  EXPECT_TRUE(g.rule("fetch")->dormant);
  EXPECT_TRUE(g.rule("handOver")->dormant);
  EXPECT_FALSE(g.rule("grasp")->dormant);
  const Rule* combo = g.rule("fetchAndHandOver");
  EXPECT_EQ(combo->kind, Rule::Kind::kCombo);
  ASSERT_EQ(combo->atoms.size(), 2u);
  EXPECT_EQ(combo->atoms[0].rule, "fetch");
  EXPECT_EQ(combo->atoms[0].alias, "take");
  ASSERT_EQ(combo->equivalences.size(), 2u);
  EXPECT_EQ(combo->equivalences[1][0].alias, "take");
  EXPECT_EQ(combo->equivalences[1][0].var, "m");
  EXPECT_TRUE(g.rule("walkAndGreet")->atoms[0].optional);
  EXPECT_FALSE(g.rule("walkAndGreet")->atoms[1].optional);
}

TEST(AgmGrammarTest, IncludePullsRulesInRelativeToTheIncludingFile) {
  const Grammar g = load("household.aggl");
  ASSERT_EQ(g.includes.size(), 1u);
  EXPECT_NE(g.includes[0].find("household_people.aggl"), std::string::npos);
  ASSERT_NE(g.rule("greet"), nullptr);
  EXPECT_NE(g.rule("greet")->file.find("household_people.aggl"), std::string::npos);
  EXPECT_NE(g.rule("grasp")->file.find("household.aggl"), std::string::npos);
  // Text without a file of its own reads no include.
  auto text = parse_grammar("name=x\n===\ninclude(household_people.aggl)\n", "x.aggl");
  ASSERT_FALSE(text.ok());
  EXPECT_NE(text.error().message.find("x.aggl:3:1: include(household_people.aggl) needs a file"),
            std::string::npos)
      << text.error().message;
  // ... unless told where to look.
  GrammarLoadOptions opt;
  opt.read_includes = true;
  opt.base_dir = kDir;
  auto with_dir = parse_grammar("name=x\n===\ninclude(household_people.aggl)\n", "x.aggl", opt);
  ASSERT_TRUE(with_dir.ok()) << with_dir.error().message;
  EXPECT_NE(with_dir->rule("greet"), nullptr);
}

TEST(AgmGrammarTest, IncludeCyclesAreRefused) {
  auto g = load_grammar_file(kDir + "cycle_a.aggl");
  ASSERT_FALSE(g.ok());
  EXPECT_EQ(g.error().code, ErrorCode::kMalformed);
  EXPECT_NE(g.error().message.find("closes a cycle"), std::string::npos) << g.error().message;
  EXPECT_NE(g.error().message.find("cycle_a.aggl:3:1:"), std::string::npos) << g.error().message;
  EXPECT_NE(g.error().message.find("cycle_b.aggl:3:1:"), std::string::npos) << g.error().message;
}

TEST(AgmGrammarTest, OlderFilesWithoutTypesAndNumberNamesLoad) {
  const Grammar g = load("untyped.aggl");
  const Rule* open = g.rule("open");
  ASSERT_NE(open, nullptr);
  EXPECT_EQ(open->lhs.nodes[0].var, "1");
  EXPECT_TRUE(g.types.known("door"));
  EXPECT_TRUE(g.notes.empty()) << "no types block: every type is implicitly its own";
  World w;
  w.checker = GrammarChecker(g);
  w.add("door", "frontDoor");
  w.add("robot", "robot");
  w.link("robot", "frontDoor", "near");
  w.link("frontDoor", "frontDoor", "closed");
  w.check_from_now();
  ASSERT_TRUE(w.change({"-frontDoor frontDoor closed", "+frontDoor frontDoor open"}).ok());
  EXPECT_EQ(w.last.rule, "open");
}

TEST(AgmGrammarTest, ErrorsNameFileLineColumnWhatWasExpectedAndWhatWasFound) {
  struct Case {
    const char* text;
    const char* want;
  } cases[] = {
      {"name=x\nfontName=Arial\nrule r : active { }", "g.aggl:3:6: expected '='"},
      {"name=x\n===\ntypes { (mug : object) }\n===\n", "g.aggl:3:16: unknown base type 'object'"},
      {"name=x\n===\nr : "
       "active(1)\n{\n\t{\n\t\ta:room(0,0)\n\t\ta->b(way)\n\t}\n\t=>\n\t{\n\t}\n}\n",
       "g.aggl:7:3: link uses undeclared variable 'b'"},
      {"name=x\n===\nr : sometimes(1) { { } => { } }",
       "g.aggl:3:5: expected 'active' or 'passive', found 'sometimes'"},
      {"name=x\n===\nr : active(1) { { a:t } => { a:t } precondition { (in a z) } }",
       "g.aggl:3:57: unknown variable 'z'"},
      {"name=x\n===\nr : active(1) { { a:t } => { a:t } precondition { (create b t) } }",
       "g.aggl:3:52: 'create' changes the graph: it belongs in an effect"},
      {"name=x\n===\nr : active(1) { { a:t } => { a:t } effect { (or (in a a) (on a a)) } }",
       "g.aggl:3:46: 'or' in an effect"},
      {"name=x\n===\nr : active(1) { { a:t } => { a:t } effect { (not (and (in a a))) } }",
       "g.aggl:3:50: (not (and ...)): an effect's 'not' removes an edge"},
      {"name=x\n===\nr : active(1) { { a:t } => { a:t } effect { (in a a) { } }",
       "g.aggl:3:54: expected '}' to close the effect, found '{'"},
      {"name=x\n===\nr : active(1) { { a:t } => { a:t } precondition { <f a> } }",
       "g.aggl:3:51: a function call <...>"},
      {"name=x\n===\nr : active(1) success(1.5) { { } => { } }",
       "g.aggl:3:23: a probability of success of 1.5"},
      {"name=x\n===\nr : active(1) { { a:t(1,) } => { } }",
       "g.aggl:3:25: expected the node's y position, found ')'"},
  };
  for (const auto& c : cases) {
    auto g = parse_grammar(c.text, "g.aggl");
    ASSERT_FALSE(g.ok()) << c.text;
    EXPECT_EQ(g.error().code, ErrorCode::kMalformed) << c.text;
    EXPECT_NE(g.error().message.find(c.want), std::string::npos)
        << "want: " << c.want << "\ngot:  " << g.error().message;
  }
}

TEST(AgmGrammarTest, WhatAgmToleratesLoadsWithANote) {
  auto g = parse_grammar(R"(name=x
===
r : active(1) { { a:t } => { a:t a->a(x) } effect { (y a a) ) } }
r : active(2) { { a:t } => { a:t a->a(z) } }
c : active(1) { nothing as n where: n.a = n.b }
d : active(1) { r as s r as q where: s.a = q.a  s.w = q.a }
e : active(1) { r as s where: r.a = s.a }
)",
                         "g.aggl");
  ASSERT_TRUE(g.ok()) << g.error().message;
  auto has = [](const std::vector<std::string>& notes, const std::string& what) {
    for (const std::string& n : notes)
      if (n.find(what) != std::string::npos) return true;
    return false;
  };
  // A name defined again: the later definition stands (AGM's planner keeps the last method).
  EXPECT_EQ(g->rule("r")->cost, 2);
  EXPECT_EQ(g->rules.size(), 4u);
  EXPECT_TRUE(has(
      g->notes,
      "g.aggl:4:1: rule 'r' is defined again (first at g.aggl:3): the later definition stands"));
  // What follows a formula is ignored, as AGM's parser does.
  EXPECT_TRUE(has(g->notes, "g.aggl:3:61: text after the effect's formula, from ')', is ignored"));
  // Combos AGM's planner would fail on are left out; an unknown variable is ignored.
  const GrammarChecker checker(*g);
  const auto& notes = checker.notes();
  EXPECT_TRUE(has(notes,
                  "g.aggl:5:17: combo rule 'c' uses rule 'nothing', which is not defined: the "
                  "combo is left out"));
  EXPECT_TRUE(has(notes, "g.aggl:6:49: 's.w': rule 'r' has no variable 'w': ignored"));
  EXPECT_TRUE(has(notes,
                  "g.aggl:7:31: combo rule 'e' names alias 'r', which none of its steps has (did "
                  "you mean 's', the "
                  "alias of rule 'r'?): the combo is left out"));
  EXPECT_EQ(notes.size(), 3u);
}

// ------------------------------------------------------------------ the guard, with AGM's meaning

// robot in the kitchen (a way to the hall), holding nothing; a mug and a tray in the kitchen.
struct Household : World {
  Household() {
    add("robot", "robot");
    add("room", "kitchen");
    add("room", "hall");
    add("mug", "mug");
    add("tray", "tray");
    add("person", "ann");
    add("person", "bob");
    link("robot", "kitchen", "in");
    link("kitchen", "hall", "way");
    link("mug", "kitchen", "in");
    link("tray", "kitchen", "in");
    link("robot", "mug", "reach");
    check_from_now();
  }
};

TEST(AgmGuardTest, ANegatedLinkRefusesTheChangeWhenTheLinkExists) {
  Household w;
  w.g.set_commit_validator(nullptr);
  w.link("robot", "ann", "near");
  w.link("ann", "robot", "ignores");
  w.check_from_now();
  // wave needs ann->robot(ignores) absent.
  Status st = w.change({"+robot ann waved"});
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.error().message.find(
                "closest rule 'wave' fails: it forbids the edge p->r(ignores), which exists"),
            std::string::npos)
      << st.error().message;
  w.g.set_commit_validator(nullptr);
  ASSERT_TRUE(w.change({"-ann robot ignores"}).ok());
  w.check_from_now();
  ASSERT_TRUE(w.change({"+robot ann waved"}).ok());
  EXPECT_EQ(w.last.rule, "wave");
  // grasp: the object not held yet and the hands empty (r->r(handsFull)*, a unary predicate).
  ASSERT_TRUE(w.change({"+mug robot in", "+robot robot handsFull"}).ok());
  EXPECT_EQ(w.last.rule, "grasp");
  // A '*' link on both sides of release's right-hand side: the predicate goes.
  ASSERT_TRUE(w.change({"-mug robot in", "-robot robot handsFull"}).ok());
  EXPECT_EQ(w.last.rule, "release");
}

TEST(AgmGuardTest, ARightHandSideNegatedLinkIsAbsentAfterTheChange) {
  Household w;
  const Rule* put = w.checker.grammar().rule("putDown");
  ASSERT_TRUE(put->effect.has_value()) << "r->r(handsFull)* only on the right: removed if there";
  w.g.set_commit_validator(nullptr);
  ASSERT_TRUE(w.change({"+mug robot in", "+robot robot handsFull", "-mug kitchen in"}).ok());
  w.check_from_now();
  // The hands are full: putting the mug down empties them, in the same change.
  EXPECT_FALSE(w.change({"-mug robot in", "+mug kitchen in"}).ok()) << "the hands would stay full";
  ASSERT_TRUE(w.change({"-mug robot in", "+mug kitchen in", "-robot robot handsFull"}).ok());
  EXPECT_EQ(w.last.rule, "putDown");
  // Hands already empty: nothing to remove.
  w.g.set_commit_validator(nullptr);
  ASSERT_TRUE(w.change({"+tray robot in", "-tray kitchen in"}).ok());
  w.check_from_now();
  ASSERT_TRUE(w.change({"-tray robot in", "+tray kitchen in"}).ok());
  EXPECT_EQ(w.last.rule, "putDown");
}

TEST(AgmGuardTest, AnEffectsForallAppliesToEveryMatch) {
  Household w;
  w.g.set_commit_validator(nullptr);
  ASSERT_TRUE(w.change({"+mug robot in", "+tray robot in"}).ok());  // the robot carries both
  w.add("object", "chair");
  w.link("chair", "kitchen", "in");  // not carried
  w.check_from_now();
  // Leaving one carried object behind is refused...
  Status st = w.change({"-robot kitchen in", "+robot hall in", "-mug kitchen in", "+mug hall in"});
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.error().message.find("closest rule 'changeRoom'"), std::string::npos)
      << st.error().message;
  EXPECT_NE(st.error().message.find("effect"), std::string::npos) << st.error().message;
  // ... so is moving what it does not carry ...
  st = w.change({"-robot kitchen in", "+robot hall in", "-mug kitchen in", "+mug hall in",
                 "-tray kitchen in", "+tray hall in", "-chair kitchen in", "+chair hall in"});
  ASSERT_FALSE(st.ok());
  // ... and moving exactly the carried ones is one application of changeRoom.
  ASSERT_TRUE(w.change({"-robot kitchen in", "+robot hall in", "-mug kitchen in", "+mug hall in",
                        "-tray kitchen in", "+tray hall in"})
                  .ok());
  EXPECT_EQ(w.last.rule, "changeRoom");
  EXPECT_TRUE(w.has("chair", "kitchen", "in"));
}

TEST(AgmGuardTest, PreconditionsWithExistsForallOrNotAndSameNodeDecide) {
  Household w;
  // exists: somebody must be in the room.
  Status st = w.change({"+kitchen kitchen explored"});
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.error().message.find("precondition"), std::string::npos) << st.error().message;
  w.g.set_commit_validator(nullptr);
  w.link("ann", "kitchen", "in");
  w.link("kitchen", "kitchen", "open");
  w.check_from_now();
  ASSERT_TRUE(w.change({"+kitchen kitchen explored"}).ok());
  EXPECT_EQ(w.last.rule, "lookAround");
  // forall + '=': only the owner may be in the room (ann is; she may close it, bob may not).
  st = w.change({"-kitchen kitchen open"});
  ASSERT_TRUE(st.ok()) << st.error().message;
  EXPECT_EQ(w.last.rule, "closeDoor");
  w.g.set_commit_validator(nullptr);
  w.link("kitchen", "kitchen", "open");
  w.link("bob", "kitchen", "in");
  w.check_from_now();
  st = w.change({"-kitchen kitchen open"});
  ASSERT_FALSE(st.ok()) << "two people in the room: whoever plays 'owner', the other is not them";
  // not: the owner must be awake.
  w.g.set_commit_validator(nullptr);
  ASSERT_TRUE(w.change({"-bob kitchen in"}).ok());
  w.link("ann", "ann", "asleep");
  w.check_from_now();
  EXPECT_FALSE(w.change({"-kitchen kitchen open"}).ok());
  // or, over unary predicates: low or empty.
  EXPECT_FALSE(w.change({"+robot robot charging"}).ok());
  w.g.set_commit_validator(nullptr);
  w.link("robot", "robot", "empty");
  w.check_from_now();
  ASSERT_TRUE(w.change({"+robot robot charging"}).ok());
  EXPECT_EQ(w.last.rule, "startCharging");
}

TEST(AgmGuardTest, ARetypeRuleAcceptsExactlyTheRetype) {
  Household w;
  w.g.set_commit_validator(nullptr);
  w.add("unknownObject", "thing");
  w.link("robot", "thing", "see");
  w.link("thing", "kitchen", "in");
  w.check_from_now();
  auto retype = [&](const char* type, bool extra) {
    return w.commit([&](graph::Transaction& tx) {
      auto fresh = replace_node_type(tx, w.id("thing"), type);
      ASSERT_TRUE(fresh.ok());
      if (extra) {
        EXPECT_TRUE(tx.insert_edge(w.id("robot"), *fresh, Symbol("reach")).ok());
      }
    });
  };
  // Not to a type the rule does not name, nor with another change.
  Status st = retype("mug", false);
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.error().message.find("retype"), std::string::npos) << st.error().message;
  EXPECT_FALSE(retype("knownObject", true).ok());
  // Exactly the retype: classify. The node keeps its name and edges.
  ASSERT_TRUE(retype("knownObject", false).ok());
  EXPECT_EQ(w.last.rule, "classify");
  EXPECT_EQ(w.g.type_of(w.id("thing")).str(), "knownObject");
  EXPECT_TRUE(w.has("robot", "thing", "see"));
  EXPECT_TRUE(w.has("thing", "kitchen", "in"));
}

TEST(AgmGuardTest, EffectsCreateDeleteAndRetypeNodes) {
  Household w;
  w.g.set_commit_validator(nullptr);
  w.add("table", "table");
  w.add("mug", "cup");
  w.add("object", "plate");
  w.link("robot", "table", "reach");
  w.link("cup", "table", "on");
  w.link("plate", "table", "on");
  w.check_from_now();
  // clearTable deletes every object on the table.
  auto del = [&](std::initializer_list<const char*> names) {
    return w.commit([&](graph::Transaction& tx) {
      for (const char* n : names) EXPECT_TRUE(tx.delete_node(w.id(n)).ok());
    });
  };
  EXPECT_FALSE(del({"cup"}).ok()) << "the plate stays: not what the effect does";
  ASSERT_TRUE(del({"cup", "plate"}).ok());
  EXPECT_EQ(w.last.rule, "clearTable");
  // setTable creates a mug on the table.
  {
    auto tx = w.g.begin();
    ASSERT_TRUE(tx.insert_edge(w.id("table"), w.id("table"), Symbol("set")).ok());
    EXPECT_FALSE(tx.commit().ok()) << "without the mug the effect makes";
  }
  {
    auto tx = w.g.begin();
    ASSERT_TRUE(tx.insert_edge(w.id("table"), w.id("table"), Symbol("set")).ok());
    NodeId m = *tx.create_node("mug", "newMug");
    ASSERT_TRUE(tx.insert_edge(m, w.id("table"), Symbol("on")).ok());
    ASSERT_TRUE(tx.commit().ok());
    EXPECT_EQ(w.last.rule, "setTable");
  }
  // recogniseAll retypes the unknown objects in the room the robot does not hold.
  w.g.set_commit_validator(nullptr);
  w.add("unknownObject", "u1");
  w.add("unknownObject", "u2");
  w.add("unknownObject", "held");
  w.link("u1", "kitchen", "in");
  w.link("u2", "kitchen", "in");
  w.link("held", "kitchen", "in");
  w.link("held", "robot", "in");
  w.check_from_now();
  auto recognise = [&](std::initializer_list<const char*> names) {
    return w.commit([&](graph::Transaction& tx) {
      for (const char* n : names) EXPECT_TRUE(replace_node_type(tx, w.id(n), "knownObject").ok());
    });
  };
  EXPECT_FALSE(recognise({"u1"}).ok());
  EXPECT_FALSE(recognise({"u1", "u2", "held"}).ok());
  ASSERT_TRUE(recognise({"u1", "u2"}).ok());
  EXPECT_EQ(w.last.rule, "recogniseAll");
}

TEST(AgmGuardTest, IncludedRulesApply) {
  Household w;
  w.g.set_commit_validator(nullptr);
  w.link("ann", "kitchen", "in");
  w.check_from_now();
  ASSERT_TRUE(w.change({"+robot ann greeted"}).ok());
  EXPECT_EQ(w.last.rule, "greet");
}

TEST(AgmGuardTest, HierarchicalRulesAreNotOneChangeDormantRulesAre) {
  Household w;
  w.g.set_commit_validator(nullptr);
  w.link("robot", "ann", "near");
  w.check_from_now();
  // serve's rewrite (the mug to ann) as one change without fetching it first: no rule has it,
  // and a claim of 'serve' is refused as hierarchical.
  auto tx = w.g.begin();
  ASSERT_TRUE(tx.delete_edge(w.id("robot"), w.id("mug"), Symbol("reach")).ok());
  ASSERT_TRUE(tx.insert_edge(w.id("mug"), w.id("ann"), Symbol("in")).ok());
  EXPECT_FALSE(w.checker.check(w.g, tx.ops()).ok());
  RuleMatch claim{"serve", {{"m", w.id("mug")}, {"p", w.id("ann")}, {"r", w.id("robot")}}};
  Status st = w.checker.verify(w.g, tx.ops(), claim);
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.error().message.find("hierarchical"), std::string::npos) << st.error().message;
  tx.abort();
  // fetch is dormant (a planner wakes it up through serve), yet a valid change.
  ASSERT_TRUE(w.change({"+mug robot in", "+robot robot handsFull"}).ok());
  EXPECT_TRUE(w.last.rule == "fetch" || w.last.rule == "grasp") << w.last.rule;
}

TEST(AgmGuardTest, ComboRulesApplyTheirStepsAsOneChange) {
  Household w;
  w.g.set_commit_validator(nullptr);
  w.link("robot", "ann", "near");
  w.link("bob", "hall", "in");
  w.check_from_now();
  // fetch then handOver, in one change: the mug ends with ann, the hands empty again.
  ASSERT_TRUE(w.change({"+mug ann in"}).ok());
  EXPECT_EQ(w.last.rule, "fetchAndHandOver");
  std::map<std::string, NodeId> b(w.last.binding.begin(), w.last.binding.end());
  EXPECT_EQ(b.at("take.m"), w.id("mug"));
  EXPECT_EQ(b.at("give.p"), w.id("ann"));
  // walkAndGreet: walk to the hall and greet bob there...
  ASSERT_TRUE(w.change({"-robot kitchen in", "+robot hall in", "+robot bob greeted"}).ok());
  EXPECT_EQ(w.last.rule, "walkAndGreet");
  // ... but not greet somebody in another room on the way.
  w.g.set_commit_validator(nullptr);
  w.link("hall", "kitchen", "way");
  w.link("ann", "hall", "in");
  w.check_from_now();
  Status st = w.change({"-robot hall in", "+robot kitchen in", "+robot ann greeted"});
  EXPECT_FALSE(st.ok()) << w.last.rule;
}

TEST(AgmGuardTest, ReceiversVerifyClaimsOfRetypesEffectsAndCombos) {
  graph::Graph a(ReplicaId{fnv1a64("a"), 1}), b(ReplicaId{fnv1a64("b"), 1});
  std::vector<std::vector<std::uint8_t>> wire;
  a.set_delta_sink([&](const graph::GraphDelta& d) { wire.push_back(graph::encode(d)); });
  auto flush = [&] {
    for (const auto& m : wire) b.merge(*graph::decode(m));
    wire.clear();
  };
  {
    auto tx = a.begin();
    NodeId robot = *tx.create_node("robot", "robot");
    NodeId kitchen = *tx.create_node("room", "kitchen");
    NodeId hall = *tx.create_node("room", "hall");
    NodeId mug = *tx.create_node("mug", "mug");
    NodeId thing = *tx.create_node("unknownObject", "thing");
    ASSERT_TRUE(tx.insert_edge(robot, kitchen, Symbol("in")).ok());
    ASSERT_TRUE(tx.insert_edge(kitchen, hall, Symbol("way")).ok());
    ASSERT_TRUE(tx.insert_edge(mug, robot, Symbol("in")).ok());
    ASSERT_TRUE(tx.insert_edge(mug, kitchen, Symbol("in")).ok());
    ASSERT_TRUE(tx.insert_edge(robot, thing, Symbol("see")).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  flush();
  GrammarGuard ga(a, GrammarChecker(load("household.aggl")), "a");
  ga.install();
  GrammarGuard gb(b, GrammarChecker(load("household.aggl")), "b");
  std::vector<std::string> complaints;
  gb.on_unverified([&](const ReplicaId&, const Error& e) { complaints.push_back(e.message); });
  {  // an effect: the carried mug moves too
    auto tx = a.begin();
    ASSERT_TRUE(tx.delete_edge(*a.find_node("robot"), *a.find_node("kitchen"), Symbol("in")).ok());
    ASSERT_TRUE(tx.insert_edge(*a.find_node("robot"), *a.find_node("hall"), Symbol("in")).ok());
    ASSERT_TRUE(tx.delete_edge(*a.find_node("mug"), *a.find_node("kitchen"), Symbol("in")).ok());
    ASSERT_TRUE(tx.insert_edge(*a.find_node("mug"), *a.find_node("hall"), Symbol("in")).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  {  // a retype
    auto tx = a.begin();
    ASSERT_TRUE(replace_node_type(tx, *a.find_node("thing"), "knownObject").ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  flush();
  EXPECT_TRUE(complaints.empty()) << complaints.front();
  EXPECT_EQ(gb.deltas_verified(), 2u);
  EXPECT_EQ(b.type_of(*b.find_node("thing")).str(), "knownObject");
  EXPECT_EQ(a.digest(), b.digest());
}

}  // namespace
}  // namespace quiver::agents
