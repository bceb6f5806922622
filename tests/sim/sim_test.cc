// Many seeded fault schedules: every run must converge with no invariant violation.

#include "quiver/sim/simulator.h"

#include <gtest/gtest.h>

#include <cstdlib>

#include "test_seed.h"

namespace quiver::sim {
namespace {

int schedules(int fallback) {
  if (std::getenv("QUIVER_SEED")) return 1;
  if (std::getenv("QUIVER_SCHEDULES")) return quiver::testing::count_from_env("QUIVER_SCHEDULES", fallback);
  return quiver::testing::seed_count(fallback);
}

// Half of the 2,000+ schedules per CI run (the other half is the next test, so ctest can run
// them on both cores).
void run_range(std::uint64_t base, int n, int steps) {
  ASSERT_GT(n, 0) << "no schedule to run";
  int failures = 0, ran = 0;
  SimResult worst;
  std::int64_t max_settle = 0;
  for (int i = 0; i < n; ++i) {
    SimConfig c = mixed_config(base + i, steps);
    SimResult r = run_simulation(c);
    ++ran;
    max_settle = std::max(max_settle, r.settle_ms);
    if (!r.ok()) {
      ++failures;
      ADD_FAILURE() << "schedule failed (replay: QUIVER_SEED=" << c.seed << "): loss=" << c.faults.loss
                    << " dup=" << c.faults.dup << " reorder=" << c.faults.reorder
                    << " partitions=" << c.faults.partitions << " crashes=" << c.faults.crashes << "\n"
                    << r.to_json();
      if (failures > 5) break;
    }
  }
  if (failures == 0)
    std::printf("[sim] %d schedules from seed %llu: all converged, longest settle %lld ms (virtual)\n", ran,
                static_cast<unsigned long long>(base), static_cast<long long>(max_settle));
  else
    std::printf("[sim] %d of %d schedules run from seed %llu FAILED (stopped after %d failures)\n", failures, ran,
                static_cast<unsigned long long>(base), failures);
}

TEST(SimTest, FaultSchedulesConvergeA) {
  const auto base = quiver::testing::base_seed("SimTest.FaultSchedulesConvergeA", 1);
  run_range(base, schedules(1000), 120);
}

TEST(SimTest, FaultSchedulesConvergeB) {
  const auto base = quiver::testing::base_seed("SimTest.FaultSchedulesConvergeB", 100001);
  run_range(base, schedules(1000), 120);
}

TEST(SimTest, ASeedReplaysExactly) {
  SimConfig c = mixed_config(424242, 150);
  c.faults.loss = 0.3;
  c.faults.dup = 0.1;
  c.faults.reorder = true;
  c.faults.partitions = true;
  c.faults.crashes = true;
  std::string a = run_simulation(c).to_json();
  std::string b = run_simulation(c).to_json();
  EXPECT_EQ(a, b);
  c.seed += 1;
  EXPECT_NE(run_simulation(c).to_json(), a) << "a different seed gives a different run";
}

TEST(SimTest, HeavyLossStillConverges) {
  SimConfig c;
  c.seed = 7;
  c.agents = 6;
  c.steps = 300;
  c.faults.loss = 0.5;
  c.faults.reorder = true;
  c.faults.dup = 0.2;
  SimResult r = run_simulation(c);
  EXPECT_TRUE(r.ok()) << r.to_json();
  EXPECT_GT(r.dropped, r.messages / 3) << "the network really lost frames";
}

TEST(SimTest, CrashedAgentsRejoinUnderNewIncarnations) {
  SimConfig c;
  c.seed = 11;
  c.agents = 5;
  c.steps = 300;
  c.faults.crashes = true;
  SimResult r = run_simulation(c);
  EXPECT_TRUE(r.ok()) << r.to_json();
  EXPECT_GT(r.crashes, 0u);
}

}  // namespace
}  // namespace quiver::sim
