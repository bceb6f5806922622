// The AGM scenarios in the simulator: without faults every exact check holds (changeRoom at each
// crossing, reach below the threshold once, the grasp paused by the nudge, one grasp, equal
// replicas); a control without hysteresis fails the reach check (the checks can fail); seeded
// fault schedules (partitions, loss, kill -9 and restart of any agent) keep the facts that must
// survive them; a seed replays exactly.
#include "quiver/sim/agm_scenario.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "test_seed.h"

namespace quiver::sim {
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

}  // namespace
}  // namespace quiver::sim
