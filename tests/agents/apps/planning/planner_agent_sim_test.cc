// The planner agent in the simulator: it writes its plan into the graph, another agent (a step
// executor) reads it from its own replica and executes the steps under the domain grammar, and
// when the world deviates (a third agent moves the robot) the planner plans again. No
// executive: the agents only read and write the graph.

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "quiver/agents/rules/mission/mission.h"
#include "quiver/agents/apps/planning/planner_agent.h"
#include "quiver/graph/world_file.h"
#include "quiver/interop/agm.h"
#include "quiver/sim/agent_host.h"
#include "quiver/sim/simulator.h"

namespace quiver::agents::planner {
using namespace quiver::agents::planning;  // the planner agent under test
namespace {

constexpr std::int64_t kMs = 1'000'000;
constexpr std::int64_t kSecond = 1'000 * kMs;
const std::string kDir = std::string(QUIVER_PLANNER_FIXTURES) + "/";

std::string read(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// The warehouse world with a plan node, as a world file every replica is seeded with.
std::string world_json() {
  graph::Graph g{graph::ReplicaId{3, 1}};
  auto r = interop::import_agm_file(g, kDir + "warehouse.xml");
  EXPECT_TRUE(r.ok()) << r.error().to_string();
  auto tx = g.begin();
  EXPECT_TRUE(tx.create_node("plan", "plan").ok());
  EXPECT_TRUE(tx.commit().ok());
  return graph::save_world(g);
}

// An agent that does nothing by itself: the test writes "perception" changes through it.
class Idle final : public Agent {
 public:
  Idle() : Agent("perception") {}
  void setup(AgentContext&) override {}
};

struct SimRun {
  std::unique_ptr<sim::AgentHost> host;
  int planner = -1, executor = -1, perception = -1;
  std::vector<std::string> log;

  explicit SimRun(const std::string& mission_file) {
    const std::string domain = read(kDir + "warehouse.aggl");
    PlannerAgentOptions po;
    po.domain_text = domain;
    po.domain_source = "warehouse.aggl";
    po.mission_text = read(kDir + mission_file);
    po.mission_source = mission_file;
    po.planner.max_expansions = 200'000;
    StepExecutorOptions eo;
    eo.domain_text = domain;
    eo.domain_source = "warehouse.aggl";
    eo.step_ns = 400 * kMs;
    std::vector<sim::SimAgentSpec> specs;
    specs.push_back({"mission_planner", [po] { return std::make_unique<PlannerAgent>(po); }});
    specs.push_back({"executor", [eo] { return std::make_unique<StepExecutor>(eo); }});
    specs.push_back({"perception", [] { return std::make_unique<Idle>(); }});
    sim::AgentHostOptions ho;
    ho.seed = 5;
    ho.replicator = sim::SimConfig::default_replicator();
    ho.world_json = world_json();
    ho.log = [this](std::int64_t t, const std::string& line) {
      log.push_back(std::to_string(t / kMs) + " ms: " + line);
    };
    host = std::make_unique<sim::AgentHost>(std::move(specs), ho);
    planner = host->index("mission_planner");
    executor = host->index("executor");
    perception = host->index("perception");
    EXPECT_TRUE(host->start().ok());
  }
  std::string plan_attr(int agent, const char* name) {
    graph::Graph* g = host->graph(agent);
    if (!g) return {};
    auto n = g->find_node("plan");
    if (!n) return {};
    const graph::Value* v = g->attr(*n, name);
    if (!v) return {};
    if (const auto* s = v->get_if<std::string>()) return *s;
    if (const auto* i = v->get_if<std::int64_t>()) return std::to_string(*i);
    return {};
  }
  bool run_until(const std::function<bool()>& done, std::int64_t limit_ns) {
    const std::int64_t end = host->now() + limit_ns;
    while (host->now() < end) {
      if (done()) return true;
      host->run_until(host->now() + 10 * kMs);
    }
    return done();
  }
  std::string dump() {
    std::string s;
    for (const std::string& l : log) s += l + "\n";
    return s;
  }
};

TEST(PlannerAgentSimTest, AnotherAgentReadsThePlanFromTheGraphAndExecutesIt) {
  SimRun run("parcel_to_hall.aggt");
  ASSERT_TRUE(run.run_until([&] { return run.plan_attr(run.executor, "status") == "executing"; }, 5 * kSecond))
      << run.dump();
  // The executor's replica holds the plan the planner wrote.
  const std::string steps = run.plan_attr(run.executor, "steps");
  EXPECT_EQ(steps, run.plan_attr(run.planner, "steps"));
  EXPECT_EQ(std::count(steps.begin(), steps.end(), '\n'), 9) << steps;
  ASSERT_TRUE(run.run_until([&] { return run.plan_attr(run.perception, "status") == "achieved"; }, 30 * kSecond))
      << run.dump();
  auto* ex = dynamic_cast<StepExecutor*>(run.host->agent(run.executor));
  auto* pl = dynamic_cast<PlannerAgent*>(run.host->agent(run.planner));
  ASSERT_TRUE(ex && pl);
  EXPECT_EQ(ex->executed(), 9u);
  EXPECT_EQ(pl->plans(), 1u);
  EXPECT_EQ(pl->replans(), 0u);
  // Every replica holds the mission.
  auto m = load_mission_file(kDir + "parcel_to_hall.aggt");
  ASSERT_TRUE(m.ok());
  for (int i = 0; i < run.host->size(); ++i) EXPECT_TRUE(check_mission(*m, *run.host->graph(i)).holds) << i;
  EXPECT_EQ(run.host->rejected(), 0u);
}

TEST(PlannerAgentSimTest, WhenTheWorldDeviatesThePlannerPlansAgain) {
  SimRun run("parcel_to_hall.aggt");
  // After three steps (the robot holds the key in the office), the robot is carried back to the
  // hall - a change no plan foresaw, written by another agent.
  ASSERT_TRUE(run.run_until([&] { return run.plan_attr(run.perception, "next") == "3"; }, 10 * kSecond)) << run.dump();
  run.host->run_until(run.host->now() + 100 * kMs);
  {
    graph::Graph& g = *run.host->graph(run.perception);
    const graph::NodeId robot = *g.find_node("robot"), hall = *g.find_node("hall");
    auto tx = g.begin();
    for (const graph::EdgeKey& e : g.edges_from(robot, "in")) ASSERT_TRUE(tx.delete_edge(e.from, e.to, e.type).ok());
    ASSERT_TRUE(tx.insert_edge(robot, hall, "in").ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  ASSERT_TRUE(run.run_until([&] { return run.plan_attr(run.perception, "status") == "achieved"; }, 60 * kSecond))
      << run.dump();
  auto* ex = dynamic_cast<StepExecutor*>(run.host->agent(run.executor));
  auto* pl = dynamic_cast<PlannerAgent*>(run.host->agent(run.planner));
  ASSERT_TRUE(ex && pl);
  EXPECT_EQ(pl->replans(), 1u) << run.dump();
  for (const std::string& line : run.log)
    if (line.find("Planner") != std::string::npos || line.find("Executor") != std::string::npos)
      std::printf("[planner-agent] %s\n", line.c_str());
  EXPECT_EQ(run.plan_attr(run.executor, "replans"), "1");
  EXPECT_EQ(run.plan_attr(run.executor, "version"), "2");
  ASSERT_EQ(ex->versions().size(), 2u);
  auto m = load_mission_file(kDir + "parcel_to_hall.aggt");
  ASSERT_TRUE(m.ok());
  for (int i = 0; i < run.host->size(); ++i) EXPECT_TRUE(check_mission(*m, *run.host->graph(i)).holds) << i;
}

TEST(PlannerAgentSimTest, TheMissionCanBeGivenInTheGraph) {
  // No mission option: the planner reads the plan node's `mission` attribute.
  const std::string domain = read(kDir + "warehouse.aggl");
  PlannerAgentOptions po;
  po.domain_text = domain;
  std::vector<sim::SimAgentSpec> specs;
  specs.push_back({"mission_planner", [po] { return std::make_unique<PlannerAgent>(po); }});
  specs.push_back({"perception", [] { return std::make_unique<Idle>(); }});
  sim::AgentHostOptions ho;
  ho.seed = 6;
  ho.replicator = sim::SimConfig::default_replicator();
  ho.world_json = world_json();
  sim::AgentHost host(std::move(specs), ho);
  ASSERT_TRUE(host.start().ok());
  host.run_until(host.now() + kSecond);
  graph::Graph& g = *host.graph(host.index("perception"));
  {
    auto tx = g.begin();
    ASSERT_TRUE(tx.set(*g.find_node("plan"), "mission", std::string(read(kDir + "robot_in_office.aggt"))).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  host.run_until(host.now() + kSecond);
  const graph::Value* steps = g.attr(*g.find_node("plan"), "steps");
  ASSERT_NE(steps, nullptr);
  EXPECT_EQ(*steps->get_if<std::string>(),
            "move@{'a': '10', 'b': '11', 'r': '1'}\nmove@{'a': '11', 'b': '12', 'r': '1'}\n");
}

}  // namespace
}  // namespace quiver::agents::planner
