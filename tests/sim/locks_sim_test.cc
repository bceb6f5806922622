// Priority locks under every fault mix: two agents that can hear each other never both hold a
// scope (the overlap must be zero over every seed); partitions may give double holds (AP).
// All-to-all membership, whose lease ends a partitioned peer's claims within these short
// schedules (set here, as it is the library's default); sim_gossip_test runs the same check under
// gossip.

#include <gtest/gtest.h>

#include "quiver/sim/simulator.h"
#include "test_seed.h"

namespace quiver::sim {
namespace {

TEST(LocksSimTest, ConnectedAgentsNeverBothHoldAScope) {
  const auto base = quiver::testing::base_seed("LocksSimTest.ConnectedAgentsNeverBothHoldAScope", 7000);
  const int n = quiver::testing::seed_count(300);
  std::uint64_t acquired = 0, lost = 0, expired = 0;
  std::int64_t overlap = 0, partitioned = 0;
  for (int i = 0; i < n; ++i) {
    SimConfig c = mixed_config(base + i, 150);
    c.agents = 3 + static_cast<int>((base + i) % 6);
    c.locks.enabled = true;
    c.replicator.gossip = false;
    SimResult r = run_simulation(c);
    ASSERT_TRUE(r.ok()) << "replay with QUIVER_SEED=" << c.seed << "\n" << r.to_json();
    acquired += r.lock_acquired;
    lost += r.lock_lost;
    expired += r.lock_expired;
    overlap += r.lock_overlap_connected_ns;
    partitioned += r.lock_overlap_partitioned_ns;
  }
  std::printf("[locks] %d schedules: %llu acquisitions, %llu lost, %llu expired; connected overlap %.3f ms, "
              "partitioned double holds %.1f ms (allowed)\n",
              n, static_cast<unsigned long long>(acquired), static_cast<unsigned long long>(lost),
              static_cast<unsigned long long>(expired), overlap / 1e6, partitioned / 1e6);
  EXPECT_EQ(overlap, 0);
  EXPECT_GT(acquired, 0u);
  EXPECT_GT(lost, 0u) << "preemptions and races happened";
  EXPECT_GT(partitioned, 0) << "partitions did let both sides hold (availability)";
}

}  // namespace
}  // namespace quiver::sim
