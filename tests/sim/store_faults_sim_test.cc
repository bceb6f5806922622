// Durable stores on faulty simulated disks (docs/persistence.md, DiskFaults in simulator.h):
// many seeded schedules of churn with packet loss, partitions, power cuts (one agent, or all at
// once), full disks and torn writes. Every schedule must converge (equal digests), and under
// `always` no acknowledged commit may be missing from what a store gives back. Each schedule
// prints its seed; QUIVER_STORE_SEED=S replays one schedule, QUIVER_STORE_SCHEDULES=N sets how
// many run (default 500).

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <string>

#include "quiver/base/rng.h"
#include "quiver/sim/simulator.h"

namespace quiver::sim {
namespace {

// The schedule of seed `seed`: 3 to 6 agents, `always` two times in three, every disk fault on
// or off at random.
SimConfig schedule(std::uint64_t seed) {
  Rng r(seed ^ 0x5704ef4175ULL);
  SimConfig c;
  c.seed = seed;
  c.steps = 160;
  c.agents = 3 + static_cast<int>(r.below(4));
  const double losses[] = {0.0, 0.05, 0.2};
  c.faults.loss = losses[r.below(3)];
  c.faults.dup = r.chance(0.3) ? 0.1 : 0.0;
  c.faults.reorder = r.chance(0.5);
  c.faults.partitions = r.chance(0.4);
  c.faults.crashes = true;
  c.disks.enabled = true;
  c.disks.durability = r.chance(2.0 / 3.0) ? agents::Durability::kAlways : agents::Durability::kBatch;
  c.disks.disk_full = r.chance(0.6);
  c.disks.torn_writes = r.chance(0.6);
  c.disks.power_cut_all = r.chance(0.5);
  c.settle_limit_ns = 60'000'000'000;
  return c;
}

std::uint64_t env_u64(const char* name, std::uint64_t fallback) {
  const char* v = std::getenv(name);
  return v != nullptr && *v != '\0' ? std::strtoull(v, nullptr, 10) : fallback;
}

TEST(StoreFaultsSim, ManySchedulesConvergeAndLoseNothingAcknowledged) {
  const std::uint64_t only = env_u64("QUIVER_STORE_SEED", 0);
  const std::uint64_t count = only != 0 ? 1 : env_u64("QUIVER_STORE_SCHEDULES", 500);
  const std::uint64_t first = only != 0 ? only : env_u64("QUIVER_STORE_FIRST_SEED", 1);
  SimResult total;
  int always = 0, failed = 0;
  for (std::uint64_t seed = first; seed < first + count; ++seed) {
    SimConfig c = schedule(seed);
    if (only != 0) c.log = [](std::int64_t t, const std::string& line) { std::printf("  %9.3f s  %s\n", t / 1e9, line.c_str()); };
    const SimResult r = run_simulation(c);
    const bool ok = r.ok();
    std::printf("seed %llu (%s, %d agents): %s %s\n", static_cast<unsigned long long>(seed),
                std::string(agents::to_string(c.disks.durability)).c_str(), c.agents, ok ? "ok" : "FAILED",
                r.to_json().c_str());
    if (!ok) {
      ++failed;
      ADD_FAILURE() << "seed " << seed << " failed (replay: QUIVER_STORE_SEED=" << seed
                    << " store_faults_sim_test --gtest_filter=*ManySchedules*): " << r.to_json();
    }
    always += c.disks.durability == agents::Durability::kAlways;
    total.acked += r.acked;
    total.acked_lost += r.acked_lost;
    total.power_cuts += r.power_cuts;
    total.crashes += r.crashes;
    total.torn_writes += r.torn_writes;
    total.torn_tails_dropped += r.torn_tails_dropped;
    total.writes_refused += r.writes_refused;
    total.fail_stops += r.fail_stops;
    total.store_reloads += r.store_reloads;
    total.restarts_refused += r.restarts_refused;
    total.stores_set_aside += r.stores_set_aside;
    total.compactions += r.compactions;
    total.compactions_failed += r.compactions_failed;
  }
  std::printf(
      "store faults: %llu schedules (%d always, %llu batch), %d failed; %llu commits acknowledged, %llu lost; "
      "%llu crashes (%llu power cuts besides), %llu torn writes (%llu torn tails dropped at reload), "
      "%llu writes refused for a full disk, %llu fail-stops, %llu restarts refused, %llu reloads from stores, "
      "%llu stores set aside, %llu compactions (%llu failed)\n",
      static_cast<unsigned long long>(count), always, static_cast<unsigned long long>(count - always), failed,
      static_cast<unsigned long long>(total.acked), static_cast<unsigned long long>(total.acked_lost),
      static_cast<unsigned long long>(total.crashes), static_cast<unsigned long long>(total.power_cuts),
      static_cast<unsigned long long>(total.torn_writes), static_cast<unsigned long long>(total.torn_tails_dropped),
      static_cast<unsigned long long>(total.writes_refused), static_cast<unsigned long long>(total.fail_stops),
      static_cast<unsigned long long>(total.restarts_refused), static_cast<unsigned long long>(total.store_reloads),
      static_cast<unsigned long long>(total.stores_set_aside), static_cast<unsigned long long>(total.compactions),
      static_cast<unsigned long long>(total.compactions_failed));
  if (only == 0 && count >= 30) {
    // The faults were exercised, not only configured.
    EXPECT_GT(total.torn_writes, 0u);
    EXPECT_GT(total.torn_tails_dropped, 0u);
    EXPECT_GT(total.writes_refused, 0u);
    EXPECT_GT(total.fail_stops, 0u);
    EXPECT_GT(total.acked, 0u);
  }
}

// The control: a disk that acknowledges writes and drops them must be caught, in every one of
// these schedules (agent 0 reloads without commits it acknowledged).
TEST(StoreFaultsSim, ALyingDiskIsCaught) {
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    SimConfig c = schedule(seed);
    c.disks.durability = agents::Durability::kAlways;
    c.disks.lying_disk = true;
    const SimResult r = run_simulation(c);
    std::printf("lying disk, seed %llu: %s\n", static_cast<unsigned long long>(seed), r.to_json().c_str());
    EXPECT_GT(r.acked_lost, 0u) << "seed " << seed;
    EXPECT_FALSE(r.ok()) << "seed " << seed;
  }
}

TEST(StoreFaultsSim, ASeedReplaysExactly) {
  SimConfig c = schedule(7);
  c.disks.disk_full = c.disks.torn_writes = c.disks.power_cut_all = true;
  const std::string a = run_simulation(c).to_json();
  const std::string b = run_simulation(c).to_json();
  std::printf("seed 7 twice: %s\n", a.c_str());
  EXPECT_EQ(a, b);
}

}  // namespace
}  // namespace quiver::sim
