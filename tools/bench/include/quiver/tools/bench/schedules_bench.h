#pragma once
// The fault-schedule benchmark (`quiver bench schedules`): many seeded fault schedules at a fixed
// number of agents, each run to convergence in the simulator; one JSON line with what held.

#include <cstdint>
#include <string>

namespace quiver::tools::bench {

struct SchedulesBench {
  int agents = 64;               ///< replicas in every schedule
  int count = 1000;              ///< schedules: seeds seed .. seed + count - 1
  std::uint64_t seed = 22000;    ///< the first schedule's seed
  int steps = 200;               ///< workload steps per schedule
  double max_loss = 0.3;         ///< the fault mixes' loss is capped here
  std::string protocol = "gossip";  ///< "gossip" or "all-to-all" (ReplicatorOptions::gossip)
};

/// Runs `b.count` schedules: schedule i is sim::mixed_config(seed + i) (loss, duplication,
/// reordering, partitions, crashes with restarts, each drawn from the seed) with `b.agents`
/// agents and its loss capped at `b.max_loss`. Prints a line on stderr for each schedule that
/// failed (with the seed that replays it: `quiver sim` with the same faults), then one JSON line
/// on stdout: schedules run, converged, diverged, failed, invariant violations, rejected samples, lock
/// overlaps, the faults injected in total and the longest settle time.
/// @pre b.agents in [1, 1000], b.count >= 1, b.steps >= 1, 0 <= b.max_loss <= 0.95.
/// A schedule fails unless it converged with no invariant violation, no sample rejected and no
/// lock held twice (sim::SimResult::ok()).
/// @returns 0 when no schedule failed, 1 if one did.
int run_schedules_bench(const SchedulesBench& b);

}  // namespace quiver::tools::bench
