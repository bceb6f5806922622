// The AGM scenarios in the simulator: without faults every exact check holds (changeRoom at each
// crossing, reach below the threshold once, the grasp paused by the nudge, one grasp, equal
// replicas); a control without hysteresis fails the reach check (the checks can fail); seeded
// fault schedules (partitions, loss, kill -9 and restart of any agent) keep the facts that must
// survive them; a seed replays exactly.
#include "quiver/agents/apps/agm/sim/agm_scenario.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <tuple>

#include "test_seed.h"

namespace quiver::sim {
using namespace quiver::agents::agm;  // the AGM scenarios under test
namespace {

AgmResult run(const AgmScenario& s, std::uint64_t seed) {
  AgmResult r = run_agm_scenario(s, seed);
  std::printf("seed %llu: %s\n", static_cast<unsigned long long>(seed), r.to_json().dump().c_str());
  return r;
}

TEST(AgmScenario, WithoutFaultsEveryExpectedFactHolds) {
  const std::uint64_t seed = testing::base_seed("AgmScenario.WithoutFaults", 1);
  AgmResult r = run(AgmScenario{}, seed);
  EXPECT_TRUE(r.passed) << r.to_json().dump();
  EXPECT_TRUE(r.converged);
  EXPECT_EQ(r.final_room, "kitchen");
  EXPECT_EQ(r.room_changes, 4);
  EXPECT_EQ(r.expected_room_changes, 4);
  EXPECT_EQ(r.reach_changes, 1);
  EXPECT_GE(r.pauses, 1);
  EXPECT_EQ(r.grasps, 1);
  EXPECT_GT(r.human_deliveries, 3u * 900u * 20u) << "three agents, 900 poses/s, over 20 s at least";
  EXPECT_LT(r.human_latency_p99_ms, 10.0);
}

TEST(AgmScenario, WithoutHysteresisTheReachCheckFails) {
  AgmScenario s;
  s.reach_off_m = 0.10;  // one threshold: the nudge to 0.12 m flips reach back
  s.humans = false;
  AgmResult r = run(s, 1);
  EXPECT_FALSE(r.passed);
  bool flicker = false;
  for (const auto& f : r.failures) flicker = flicker || f.find("flickered") != std::string::npos;
  EXPECT_TRUE(flicker) << r.to_json().dump();
}

TEST(AgmScenario, TheExampleFileRunsAndBadFilesNameTheValue) {
  auto s = AgmScenario::load(QUIVER_EXAMPLES "/agm/partition-mid-grasp.json");
  ASSERT_TRUE(s.ok()) << s.error().to_string();
  EXPECT_EQ(s->faults.size(), 5u);
  AgmResult r = run(*s, 1);
  EXPECT_TRUE(r.passed) << r.to_json().dump();
  EXPECT_EQ(r.kills, 1);
  EXPECT_GE(r.pauses, 1) << "cut off from localization mid-grasp";
  for (auto [text, pointer] :
       {std::pair{R"({"faults": [{"at_s": 1, "kill": "planner"}]})", "/faults/0/kill"},
        std::pair{R"({"faults": [{"at_s": 1, "partition": [["rooms"], [3]]}]})",
                  "/faults/0/partition/1/0"},
        std::pair{R"({"checks": {"crossing_lag_ms": -1}})", "/checks/crossing_lag_ms"},
        std::pair{R"({"humans_hz": 0})", "/humans_hz"},
        std::pair{R"({"patient": {}})", "/patient"}}) {
    auto bad = AgmScenario::parse(nlohmann::json::parse(text), "s.json");
    ASSERT_FALSE(bad.ok()) << text;
    EXPECT_NE(bad.error().message.find(std::string("s.json:") + pointer), std::string::npos)
        << bad.error().message;
  }
}

TEST(AgmScenario, ASeedReplaysExactly) {
  AgmScenario s = AgmScenario::random_faults(5);
  s.humans_hz = 10;  // faster; the same code paths
  const AgmResult a = run_agm_scenario(s, 5), b = run_agm_scenario(s, 5);
  EXPECT_EQ(a.to_json().dump(), b.to_json().dump());
}

TEST(AgmScenario, FaultSchedulesKeepTheFacts) {
  const std::uint64_t base = testing::base_seed("AgmScenario.FaultSchedules", 100);
  const int n = testing::seed_count(8);
  for (int k = 0; k < n; ++k) {
    const std::uint64_t seed = base + static_cast<std::uint64_t>(k);
    AgmResult r = run(AgmScenario::random_faults(seed), seed);
    EXPECT_TRUE(r.passed) << "replay: quiver sim --agm --schedules 1 --seed " << seed << "\n"
                          << r.to_json().dump();
  }
}

// Clean the table (agents/apps/agm/clean_table.h): the planner agent plans from the world, writes
// the plan into the graph, navigation and grasping follow its next step; both mugs end in the
// kitchen, one carried at a time; the plan replays through the grammar guard.
AgmScenario clean_table() {
  AgmScenario s;
  s.name = "clean-table";
  s.mission = "clean-table";
  return s;
}

TEST(AgmCleanTable, ThePlannerReachesTheMissionEndToEnd) {
  const std::uint64_t seed = testing::base_seed("AgmCleanTable.EndToEnd", 1);
  AgmResult r = run(clean_table(), seed);
  EXPECT_TRUE(r.passed) << r.to_json().dump();
  EXPECT_TRUE(r.mission_holds);
  EXPECT_EQ(r.plan_status, "achieved");
  EXPECT_EQ(r.plan_verified, "ok");
  EXPECT_EQ(r.plan_version, 1);
  EXPECT_EQ(r.replans, 0);
  EXPECT_EQ(r.plan_steps, 14) << "two trips: 4 room changes, approach, grasp and release each";
  EXPECT_EQ(r.grasps, 2);
  EXPECT_EQ(r.releases, 2);
  EXPECT_EQ(r.room_changes, 8);
  EXPECT_EQ(r.expected_room_changes, 8);
  EXPECT_EQ(r.final_room, "kitchen");
  EXPECT_TRUE(r.converged);
  EXPECT_GT(r.human_deliveries, 0u);
}

TEST(AgmCleanTable, WithoutThePlannerNothingHappensAndTheCheckFails) {
  // The control: the planner killed at once and never restarted before the limit; the mission
  // must then be reported as not holding.
  AgmScenario s = clean_table();
  s.humans = false;
  s.limit_s = 45;
  FaultEvent kill;
  kill.kind = FaultEvent::Kind::kKill;
  kill.agent = "agm-planner";
  kill.at_s = 0.0;
  s.faults.push_back(kill);
  AgmResult r = run(s, 1);
  EXPECT_FALSE(r.passed);
  EXPECT_FALSE(r.mission_holds) << r.to_json().dump();
}

TEST(AgmCleanTable, ThePlannerKilledMidPlanContinuesFromTheGraph) {
  // kill -9 of the planner during the first trip and of navigation during the second: a new
  // planner incarnation finds the plan in the graph and tracks it on.
  AgmScenario s = clean_table();
  s.humans_hz = 10;
  for (auto [at, agent, kind] : {std::tuple{8.0, "agm-planner", FaultEvent::Kind::kKill},
                                 std::tuple{9.5, "agm-planner", FaultEvent::Kind::kRestart},
                                 std::tuple{30.0, "navigation", FaultEvent::Kind::kKill},
                                 std::tuple{31.0, "navigation", FaultEvent::Kind::kRestart}}) {
    FaultEvent e;
    e.kind = kind;
    e.agent = agent;
    e.at_s = at;
    s.faults.push_back(e);
  }
  const std::uint64_t seed = testing::base_seed("AgmCleanTable.Killed", 3);
  AgmResult r = run(s, seed);
  EXPECT_TRUE(r.passed) << r.to_json().dump();
  EXPECT_EQ(r.kills, 2);
  EXPECT_TRUE(r.mission_holds);
}

TEST(AgmCleanTable, AMugPutBackOnTheTableMakesThePlannerPlanAgain) {
  // The example file: at 28 s, after the first mug was released in the kitchen, a person puts it
  // back on the table; the plan's rest no longer reaches the mission, the planner plans again
  // from the world as it is, and the robot fetches it a second time.
  auto s = AgmScenario::load(QUIVER_EXAMPLES "/agm/clean-table-put-back.json");
  ASSERT_TRUE(s.ok()) << s.error().to_string();
  s->humans_hz = 10;
  const std::uint64_t seed = testing::base_seed("AgmCleanTable.PutBack", 1);
  AgmResult r = run(*s, seed);
  EXPECT_TRUE(r.passed) << r.to_json().dump();
  EXPECT_TRUE(r.mission_holds);
  EXPECT_GE(r.replans, 1);
  EXPECT_GE(r.plan_version, 2);
  EXPECT_EQ(r.grasps, 3) << "mug twice, mug2 once";
  EXPECT_EQ(r.releases, 3);
}

TEST(AgmCleanTable, FaultSchedulesStillReachTheMission) {
  const std::uint64_t base = testing::base_seed("AgmCleanTable.FaultSchedules", 200);
  const int n = testing::seed_count(4);
  for (int k = 0; k < n; ++k) {
    const std::uint64_t seed = base + static_cast<std::uint64_t>(k);
    AgmScenario s = AgmScenario::random_faults(seed, "clean-table");
    s.humans_hz = 10;
    AgmResult r = run(s, seed);
    EXPECT_TRUE(r.passed) << "replay: quiver sim --agm --mission clean-table --schedules 1 --seed "
                          << seed << "\n"
                          << r.to_json().dump();
  }
}

TEST(AgmCleanTable, ScenarioFilesNameTheMission) {
  auto s = AgmScenario::parse(nlohmann::json::parse(
                                  R"({"mission": "clean-table", "faults": [{"at_s": 3, "kill": "agm-planner"}]})"),
                              "c.json");
  ASSERT_TRUE(s.ok()) << s.error().to_string();
  EXPECT_EQ(s->mission, "clean-table");
  auto bad = AgmScenario::parse(nlohmann::json::parse(R"({"mission": "wash-dishes"})"), "c.json");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().message.find("c.json:/mission"), std::string::npos) << bad.error().message;
}

}  // namespace
}  // namespace quiver::sim
