// The planner: known-optimal plans on a small domain written for these tests (fixtures/), every
// plan replayed through the grammar guard, A* against a brute-force search on random problems
// (seeded), the heuristic never above the true cost, hierarchical steps decomposed.

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <queue>

#include "quiver/agents/rules/grammar/grammar.h"
#include "quiver/agents/rules/mission/mission.h"
#include "quiver/agents/rules/planner/planner.h"
#include "quiver/agents/rules/planner/plan_replay.h"
#include "quiver/interop/agm.h"
#include "quiver/base/rng.h"
#include "test_seed.h"

namespace quiver::agents::planner {
namespace {

const std::string kDir = std::string(QUIVER_PLANNER_FIXTURES) + "/";

Grammar load(const std::string& file) {
  auto g = load_grammar_file(kDir + file);
  EXPECT_TRUE(g.ok()) << g.error().to_string();
  return g.ok() ? *g : Grammar{};
}

// A problem: a world (a replica), a domain and a mission, compiled.
struct Problem {
  graph::Graph g{graph::ReplicaId{9, 1}};
  Grammar grammar;
  Mission mission;
  symbolic::World world;
  std::unique_ptr<Domain> domain;
  CompiledMission goal;

  Problem(const std::string& grammar_file, const std::string& world_xml, const std::string& mission_text)
      : grammar(load(grammar_file)) {
    auto r = world_xml.find('<') == std::string::npos ? interop::import_agm_file(g, kDir + world_xml)
                                                       : interop::import_agm(g, world_xml, "world.xml");
    EXPECT_TRUE(r.ok()) << r.error().to_string();
    auto m = mission_text.find('{') == std::string::npos ? load_mission_file(kDir + mission_text)
                                                          : parse_mission(mission_text, "mission.aggt");
    EXPECT_TRUE(m.ok()) << m.error().to_string();
    mission = *m;
    compile();
  }
  void compile() {
    world = symbolic::read_world(g, grammar.types);
    domain = std::make_unique<Domain>(grammar, world.vocabulary);
    auto c = compile_mission(mission, world);
    EXPECT_TRUE(c.ok()) << c.error().to_string();
    goal = *c;
  }
  PlanResult solve(PlannerOptions o = {}) { return plan(*domain, world.state, goal, o); }
  std::vector<std::string> text(const PlanResult& r) {
    std::vector<std::string> out;
    for (const Step& s : r.steps) out.push_back(to_string(s, world));
    return out;
  }
  // Replays the plan on a copy of the world through the guard.
  Status verify(const PlanResult& r) {
    graph::Graph copy{graph::ReplicaId{10, 1}};
    copy.merge(g.state());
    // The copy holds the same nodes under the same ids: the planning world maps onto it.
    GrammarChecker checker(grammar);
    return verify_plan(copy, checker, world, r, mission);
  }
};

// Uniform-cost search written apart from the planner, over Domain::successors: the reference.
double brute_force_cost(const Problem& p, int max_world_increment = 5, std::size_t cap = 2'000'000) {
  using symbolic::State;
  struct Item {
    double g;
    std::uint64_t seq;
    std::size_t idx;
    bool operator<(const Item& o) const { return g != o.g ? g > o.g : seq > o.seq; }
  };
  std::vector<std::pair<State, double>> states{{p.world.state, 0.0}};
  std::vector<double> plain{0.0};
  std::multimap<std::uint64_t, std::size_t> index{{p.world.state.hash(), 0}};
  std::priority_queue<Item> open;
  open.push({0, 0, 0});
  std::uint64_t seq = 1;
  const std::size_t max_nodes = p.world.state.alive_count() + max_world_increment;
  std::vector<bool> none(p.domain->rule_count(), false);
  while (!open.empty() && states.size() < cap) {
    Item it = open.top();
    open.pop();
    if (it.g > states[it.idx].second) continue;
    if (mission_holds(states[it.idx].first, p.world.vocabulary, p.goal)) return it.g;
    const State cur = states[it.idx].first;
    const double pl = plain[it.idx];
    p.domain->successors(cur, none, false, [&](const Step& st, State&& next) {
      if (next.alive_count() > max_nodes) return;
      const double c = p.domain->cost(st.rule);
      const double g = it.g + c + (1 - p.domain->success(st.rule)) * (pl + c);
      auto [lo, hi] = index.equal_range(next.hash());
      for (auto i = lo; i != hi; ++i)
        if (states[i->second].first == next) {
          if (states[i->second].second <= g) return;
          states[i->second].second = g;
          plain[i->second] = pl + c;
          open.push({g, seq++, i->second});
          return;
        }
      index.emplace(next.hash(), states.size());
      states.emplace_back(std::move(next), g);
      plain.push_back(pl + c);
      open.push({g, seq++, states.size() - 1});
    });
  }
  return std::numeric_limits<double>::infinity();
}

TEST(PlannerTest, FindsTheKnownOptimalPlans) {
  struct Case {
    const char* mission;
    double cost;
    std::size_t length;
  };
  // parcel_to_hall_target.xml: the same target as AGM's XML (an <AGMModel> pattern).
  for (const Case& c : {Case{"robot_in_office.aggt", 4, 2}, Case{"parcel_to_hall.aggt", 17, 9},
                        Case{"parcel_to_hall_target.xml", 17, 9},
                        Case{"ball_in_hall.aggt", 12, 7}, Case{"two_parcels.aggt", 16, 10}}) {
    SCOPED_TRACE(c.mission);
    Problem p("warehouse.aggl", "warehouse.xml", c.mission);
    PlanResult r = p.solve();
    ASSERT_TRUE(r.found()) << r.why;
    EXPECT_EQ(r.cost, c.cost);
    EXPECT_EQ(r.steps.size(), c.length);
    EXPECT_EQ(r.cost, brute_force_cost(p));
    EXPECT_TRUE(p.verify(r).ok()) << p.verify(r).error().to_string();
  }
}

TEST(PlannerTest, ThePlanReadsAsAgmPrintsIt) {
  Problem p("warehouse.aggl", "warehouse.xml", "robot_in_office.aggt");
  PlanResult r = p.solve();
  ASSERT_TRUE(r.found());
  EXPECT_EQ(p.text(r), (std::vector<std::string>{"move@{'a': '10', 'b': '11', 'r': '1'}",
                                                 "move@{'a': '11', 'b': '12', 'r': '1'}"}));
  // And back: parse_step gives the same steps.
  for (const Step& s : r.steps) {
    auto back = parse_step(to_string(s, p.world), *p.domain, p.world);
    ASSERT_TRUE(back.ok()) << back.error().to_string();
    EXPECT_EQ(*back, s);
  }
  EXPECT_FALSE(parse_step("fly@{'r': '1'}", *p.domain, p.world).ok());
  EXPECT_FALSE(parse_step("move{'r': '1'}", *p.domain, p.world).ok());
}

TEST(PlannerTest, CreatedAndRetypedNodesReplayThroughTheGuard) {
  // ball_in_hall creates a ball (openBox); two_parcels retypes the unknown thing (identify).
  for (const char* m : {"ball_in_hall.aggt", "two_parcels.aggt"}) {
    SCOPED_TRACE(m);
    Problem p("warehouse.aggl", "warehouse.xml", m);
    PlanResult r = p.solve();
    ASSERT_TRUE(r.found()) << r.why;
    Status s = p.verify(r);
    EXPECT_TRUE(s.ok()) << s.error().to_string();
  }
}

TEST(PlannerTest, AVerificationFailsWhenTheGuardRefusesAStep) {
  Problem p("warehouse.aggl", "warehouse.xml", "robot_in_office.aggt");
  PlanResult r = p.solve();
  ASSERT_TRUE(r.found());
  // A grammar without `move` refuses the first step.
  Grammar without = p.grammar;
  std::erase_if(without.rules, [](const Rule& x) { return x.name == "move"; });
  graph::Graph copy{graph::ReplicaId{11, 1}};
  copy.merge(p.g.state());
  Status s = verify_plan(copy, GrammarChecker(without), p.world, r, p.mission);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().message.find("step 1 (move@{'a': '10', 'b': '11', 'r': '1'}): the grammar guard refuses it"),
            std::string::npos)
      << s.error().message;
}

TEST(PlannerTest, AnAchievedMissionNeedsNoStepsAndAnImpossibleOneIsProvedSo) {
  Problem done("warehouse.aggl", "warehouse.xml", "{ 1:robot 10:room 1->10(in) }");
  PlanResult r = done.solve();
  ASSERT_TRUE(r.found());
  EXPECT_TRUE(r.steps.empty());
  // No rule adds a `flies` link: the heuristic is infinite at the start.
  Problem never("warehouse.aggl", "warehouse.xml", "{ 1:robot 1->1(flies) }");
  PlanResult n = never.solve();
  EXPECT_EQ(n.outcome, PlanResult::Outcome::kUnsolvable);
  EXPECT_EQ(n.expansions, 0u);
  // A constant the world lacks.
  Problem unknown("warehouse.aggl", "warehouse.xml", "{ 1:robot 77:room 1->77(in) }");
  EXPECT_EQ(unknown.solve().outcome, PlanResult::Outcome::kUnsolvable);
}

TEST(PlannerTest, TheGrowthBoundLimitsCreatedNodes) {
  // Two balls need two boxes: there is one, so no plan; and with max_world_increment 0 not even
  // one ball may appear.
  Problem two("warehouse.aggl", "warehouse.xml", "{ a:ball b:ball }");
  EXPECT_EQ(two.solve().outcome, PlanResult::Outcome::kExhausted);
  Problem one("warehouse.aggl", "warehouse.xml", "{ a:ball }");
  EXPECT_TRUE(one.solve().found());
  PlannerOptions o;
  o.max_world_increment = 0;
  EXPECT_EQ(one.solve(o).outcome, PlanResult::Outcome::kExhausted);
}

TEST(PlannerTest, LimitsStopTheSearchWithoutAWallClock) {
  Problem p("warehouse.aggl", "warehouse.xml", "parcel_to_hall.aggt");
  PlannerOptions o;
  o.max_expansions = 3;
  PlanResult r = p.solve(o);
  EXPECT_EQ(r.outcome, PlanResult::Outcome::kLimit);
  EXPECT_EQ(r.expansions, 3u);
  // An injected clock that jumps past the deadline.
  std::int64_t t = 0;
  o.max_expansions = 0;
  o.max_time_ns = 1000;
  o.clock = [&t] { return t += 600; };
  EXPECT_EQ(p.solve(o).outcome, PlanResult::Outcome::kLimit);
}

TEST(PlannerTest, IsDeterministicAndTheHeuristicSavesExpansions) {
  Problem p("warehouse.aggl", "warehouse.xml", "two_parcels.aggt");
  PlanResult a = p.solve(), b = p.solve();
  ASSERT_TRUE(a.found());
  EXPECT_EQ(a.steps, b.steps);
  EXPECT_EQ(a.expansions, b.expansions);
  PlannerOptions blind;
  blind.heuristic = false;
  PlanResult u = p.solve(blind);
  ASSERT_TRUE(u.found());
  EXPECT_EQ(u.cost, a.cost);
  EXPECT_LT(a.expansions, u.expansions);
  std::printf("[planner] two_parcels: A* %zu expansions, uniform-cost %zu\n", a.expansions, u.expansions);
}

TEST(PlannerTest, HierarchicalStepsAreDecomposedIntoRulesTheGuardAccepts) {
  Problem p("errands.aggl", "warehouse.xml", "{ 1:robot 32:parcel 10:room 1->32(holds) 1->10(in) }");
  PlannerOptions flat;
  flat.decompose = false;
  PlanResult abstract = p.solve(flat);
  ASSERT_TRUE(abstract.found());
  ASSERT_EQ(abstract.steps.size(), 1u);
  EXPECT_TRUE(abstract.steps[0].hierarchical);
  EXPECT_EQ(abstract.steps[0].name, "fetch");
  PlanResult r = p.solve();
  ASSERT_TRUE(r.found()) << r.why;
  EXPECT_GT(r.searches, 1u);
  for (const Step& s : r.steps) EXPECT_FALSE(s.hierarchical) << s.name;
  EXPECT_EQ(r.cost, 17);  // the decomposition: the optimal way to fetch the parcel
  Status s = p.verify(r);
  EXPECT_TRUE(s.ok()) << s.error().to_string();
}

TEST(PlannerTest, PlansWithGrammarsInQuiversDialectToo) {
  // tests/agents/rules/grammar/grammars/agm.aggl: `forall` rewrites (what the robot carries moves with it), a
  // `not exists` precondition, negative edges `!a->b(l)`.
  auto grammar = load_grammar_file(std::string(QUIVER_AGENT_GRAMMARS) + "/agm.aggl");
  ASSERT_TRUE(grammar.ok()) << grammar.error().to_string();
  graph::Graph g{graph::ReplicaId{12, 1}};
  {
    auto tx = g.begin();
    auto node = [&](const char* type, const char* name, const char* id) {
      return *tx.create_node(type, name, {{"agm_id", graph::Value(std::string(id))}});
    };
    auto robot = node("robot", "robot", "1"), kitchen = node("room", "kitchen", "10"),
         hall = node("room", "hall", "11"), office = node("room", "office", "12"), mug = node("mug", "mug", "20");
    ASSERT_TRUE(tx.insert_edge(robot, kitchen, "in").ok());
    ASSERT_TRUE(tx.insert_edge(mug, kitchen, "in").ok());
    ASSERT_TRUE(tx.insert_edge(robot, mug, "reach").ok());
    ASSERT_TRUE(tx.insert_edge(kitchen, hall, "transitable").ok());
    ASSERT_TRUE(tx.insert_edge(hall, office, "transitable").ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  auto mission = parse_mission("{ 1:robot 20:mug 12:room 1->12(in) 20->12(in) }", "m.aggt");
  ASSERT_TRUE(mission.ok());
  symbolic::World world = symbolic::read_world(g, grammar->types);
  Domain domain(*grammar, world.vocabulary);
  auto goal = compile_mission(*mission, world);
  ASSERT_TRUE(goal.ok());
  PlanResult r = plan(domain, world.state, *goal);
  ASSERT_TRUE(r.found()) << r.why;
  std::vector<std::string> text;
  for (const Step& s : r.steps) text.push_back(to_string(s, world));
  EXPECT_EQ(text, (std::vector<std::string>{"grasp@{'o': '20', 'r': '1'}", "changeRoom@{'a': '10', 'b': '11', 'r': '1'}",
                                            "changeRoom@{'a': '11', 'b': '12', 'r': '1'}"}));
  EXPECT_EQ(r.cost, 3);
  Status s = verify_plan(g, GrammarChecker(*grammar), world, r, *mission);
  EXPECT_TRUE(s.ok()) << s.error().to_string();
}

// Random warehouses: rooms on a random graph of ways (some locked), a key, boxes, unknown things
// and parcels at random; a random mission. A* must cost what the brute-force search costs, its
// heuristic at the start must not exceed that, and its plan must replay through the guard.
std::string random_world(Rng& rng, int& rooms) {
  rooms = static_cast<int>(rng.range(2, 5));
  std::string xml = "<AGMModel>\n<symbol id=\"1\" type=\"robot\"/>\n";
  for (int r = 0; r < rooms; ++r) xml += "<symbol id=\"" + std::to_string(10 + r) + "\" type=\"room\"/>\n";
  std::string links = "<link src=\"1\" dst=\"" + std::to_string(10 + rng.below(rooms)) + "\" label=\"in\"/>\n";
  for (int a = 0; a < rooms; ++a)
    for (int b = 0; b < rooms; ++b) {
      if (a == b) continue;
      const double x = rng.uniform();
      const std::string label = x < 0.35 ? "way" : x < 0.45 ? "locked" : "";
      if (!label.empty())
        links += "<link src=\"" + std::to_string(10 + a) + "\" dst=\"" + std::to_string(10 + b) + "\" label=\"" +
                 label + "\"/>\n";
    }
  // A line of ways so that most problems are solvable.
  for (int a = 0; a + 1 < rooms; ++a)
    if (rng.chance(0.7))
      links += "<link src=\"" + std::to_string(10 + a) + "\" dst=\"" + std::to_string(11 + a) + "\" label=\"way\"/>\n";
  int id = 20;
  auto thing = [&](const char* type, bool full) {
    xml += "<symbol id=\"" + std::to_string(id) + "\" type=\"" + type + "\"/>\n";
    links += "<link src=\"" + std::to_string(id) + "\" dst=\"" + std::to_string(10 + rng.below(rooms)) +
             "\" label=\"at\"/>\n";
    if (full) links += "<link src=\"" + std::to_string(id) + "\" dst=\"" + std::to_string(id) + "\" label=\"full\"/>\n";
    ++id;
  };
  if (rng.chance(0.6)) thing("key", false);
  if (rng.chance(0.5)) thing("box", true);
  if (rng.chance(0.5)) thing("unknown", false);
  thing("parcel", false);
  return xml + links + "</AGMModel>\n";
}

std::string random_mission(Rng& rng, int rooms) {
  const std::string room = std::to_string(10 + rng.below(rooms));
  switch (rng.below(4)) {
    case 0:
      return "{ 1:robot " + room + ":room 1->" + room + "(in) }";
    case 1:
      return "{ p:parcel " + room + ":room p->" + room + "(at) }";
    case 2:
      return "{ b:ball " + room + ":room b->" + room + "(at) 1:robot 1->1(busy)* }";
    default:
      return "{ o:object " + room + ":room o->" + room + "(at) 1:robot 1->" + room + "(in) 1->o(holds) }";
  }
}

TEST(PlannerPropertyTest, AStarCostsWhatBruteForceCostsOnRandomProblems) {
  const std::uint64_t base = quiver::testing::base_seed("PlannerPropertyTest.AStarCostsWhatBruteForceCosts", 4242);
  const int n = quiver::testing::seed_count(60);
  int solved = 0, unsolvable = 0;
  for (int i = 0; i < n; ++i) {
    const std::uint64_t seed = base + static_cast<std::uint64_t>(i);
    Rng rng(seed);
    int rooms = 0;
    const std::string world = random_world(rng, rooms);
    const std::string mission = random_mission(rng, rooms);
    SCOPED_TRACE("replay with QUIVER_SEED=" + std::to_string(seed) + "\nmission " + mission + "\n" + world);
    Problem p("warehouse.aggl", world, mission);
    const double reference = brute_force_cost(p, 3);
    PlannerOptions o;
    o.max_world_increment = 3;
    PlanResult r = p.solve(o);
    EXPECT_LE(heuristic(*p.domain, p.world.state, p.goal), reference);
    if (std::isinf(reference)) {
      EXPECT_FALSE(r.found());
      ++unsolvable;
      continue;
    }
    ASSERT_TRUE(r.found()) << r.why;
    EXPECT_EQ(r.cost, reference);
    // h never exceeds the cost still to pay along the optimal plan.
    for (std::size_t k = 0; k < r.states.size(); ++k) {
      double rest = 0;
      for (std::size_t j = k; j < r.steps.size(); ++j) rest += p.domain->cost(r.steps[j].rule);
      EXPECT_LE(heuristic(*p.domain, r.states[k], p.goal), rest) << "state " << k;
    }
    Status s = p.verify(r);
    EXPECT_TRUE(s.ok()) << s.error().to_string();
    ++solved;
  }
  std::printf("[planner] %d random problems from seed %llu: %d solved optimally, %d without a plan\n", n,
              static_cast<unsigned long long>(base), solved, unsolvable);
  EXPECT_GT(solved, n / 2);
}

}  // namespace
}  // namespace quiver::agents::planner
