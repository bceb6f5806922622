// The gossip membership (ReplicatorOptions::gossip, issue 22) under every fault mix: seeded
// schedules converge, connected agents never both hold a lock, 256 agents converge through 30%
// loss, partitions and crashes, and what an idle agent sends does not grow with the number of
// agents (counted by the simulator, not timed).

#include <gtest/gtest.h>

#include <cstdio>

#include "quiver/sim/simulator.h"
#include "test_seed.h"

namespace quiver::sim {
namespace {

SimConfig gossip(SimConfig c) {
  c.replicator.gossip = true;
  return c;
}

TEST(GossipSimTest, FaultSchedulesConverge) {
  const auto base = quiver::testing::base_seed("GossipSimTest.FaultSchedulesConverge", 300001);
  const int n = quiver::testing::seed_count(300);
  std::int64_t max_settle = 0;
  for (int i = 0; i < n; ++i) {
    SimConfig c = gossip(mixed_config(base + i, 120));
    SimResult r = run_simulation(c);
    ASSERT_TRUE(r.ok()) << "replay with QUIVER_SEED=" << c.seed << "\n" << r.to_json();
    max_settle = std::max(max_settle, r.settle_ms);
  }
  std::printf("[gossip] %d schedules from seed %llu: all converged, longest settle %lld ms (virtual)\n", n,
              static_cast<unsigned long long>(base), static_cast<long long>(max_settle));
}

TEST(GossipSimTest, ConnectedAgentsNeverBothHoldAScope) {
  const auto base = quiver::testing::base_seed("GossipSimTest.ConnectedAgentsNeverBothHoldAScope", 307000);
  const int n = quiver::testing::seed_count(100);
  std::uint64_t acquired = 0;
  std::int64_t overlap = 0;
  for (int i = 0; i < n; ++i) {
    SimConfig c = gossip(mixed_config(base + i, 150));
    c.agents = 3 + static_cast<int>((base + i) % 6);
    c.locks.enabled = true;
    SimResult r = run_simulation(c);
    ASSERT_TRUE(r.ok()) << "replay with QUIVER_SEED=" << c.seed << "\n" << r.to_json();
    acquired += r.lock_acquired;
    overlap += r.lock_overlap_connected_ns;
  }
  std::printf("[gossip locks] %d schedules: %llu acquisitions, connected overlap %.3f ms\n", n,
              static_cast<unsigned long long>(acquired), overlap / 1e6);
  EXPECT_EQ(overlap, 0);
  EXPECT_GT(acquired, 0u);
}

TEST(GossipSimTest, TwoHundredFiftySixAgentsConvergeThroughLossPartitionsAndCrashes) {
  SimConfig c;
  c.seed = quiver::testing::base_seed("GossipSimTest.TwoHundredFiftySixAgents", 22);
  c.agents = 256;
  c.steps = 300;
  c.faults.loss = 0.3;
  c.faults.reorder = true;
  c.faults.partitions = true;
  c.faults.crashes = true;
  c.check_every_step = false;
  c = gossip(c);
  SimResult r = run_simulation(c);
  std::printf("[gossip 256] %s\n", r.to_json().c_str());
  EXPECT_TRUE(r.ok()) << "replay with QUIVER_SEED=" << c.seed;
  EXPECT_EQ(r.invariant_violations, 0u);
  EXPECT_GT(r.crashes, 0u);
  EXPECT_GT(r.partitions, 0u);
  EXPECT_GT(r.dropped, 0u);
  EXPECT_GT(r.ops, 200u);
}

// Idle traffic per agent, as the simulator counts the samples: the same at 8 and 64 agents
// (all-to-all summaries grow with N: at 64 agents they are about 60 times the 8-agent figure).
TEST(GossipSimTest, IdleTrafficPerAgentDoesNotGrowWithAgents) {
  double per_agent[2] = {0, 0};
  const int sizes[2] = {8, 64};
  for (int k = 0; k < 2; ++k) {
    SimConfig c;
    c.seed = 5;
    c.agents = sizes[k];
    c.steps = 100;
    c.idle_ns = 3'000'000'000;
    c = gossip(c);
    SimResult r = run_simulation(c);
    ASSERT_TRUE(r.ok()) << r.to_json();
    per_agent[k] = static_cast<double>(r.idle_bytes) / (3.0 * sizes[k]);
    std::printf("[gossip idle] %d agents: %.1f bytes/s per agent\n", sizes[k], per_agent[k]);
  }
  EXPECT_GT(per_agent[0], 0);
  EXPECT_LE(per_agent[1], 1.25 * per_agent[0]);
  EXPECT_LE(per_agent[1], 1024.0) << "the idle target is 1 KB/s per agent";
}

}  // namespace
}  // namespace quiver::sim
