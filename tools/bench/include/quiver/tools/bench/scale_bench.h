#pragma once
// The scaling benchmark (`quiver bench scale`): what each agent pays as the number of agents
// grows, in the simulator (the samples DDS would carry), one JSON line per number of agents.

#include <cstdint>
#include <string>
#include <vector>

namespace quiver::tools::bench {

struct ScaleBench {
  std::vector<int> agents = {4, 8, 16, 32, 64, 128};  ///< the numbers of agents, in order
  int steps = 1000;        ///< workload steps (one random agent commits per step)
  std::uint64_t seed = 5;  ///< of the workload; one run per number of agents, all with it
  double idle_s = 4.0;     ///< virtual seconds of idle time after each run, measured apart
  std::string protocol = "gossip";  ///< "gossip" or "all-to-all" (ReplicatorOptions::gossip)
  bool skip_heal = false;  ///< no second run with a partition until the end (heal_ms)
};

/// For each number of agents N, the run of `quiver sim --agents N --steps S --seed SEED` (no
/// faults, the default workload and heartbeat period): one JSON line on stdout with its ops,
/// bytes and messages, bytes and messages per op per agent, the idle traffic per second per agent
/// (`idle_s` of virtual time after the run converged, with nothing to replicate), whether it
/// converged, the run's wall time, the protocol state per replica (Replicator::protocol_bytes(),
/// largest and mean) and the bytes by message kind; then, unless `skip_heal`, a second run of the
/// same workload with the agents split in two halves from a fifth of it to its end: `heal_ms`, the
/// virtual time from the heal to convergence. scripts/plot_scale.py draws the lines as log-log curves.
/// @pre every entry of `b.agents` is in [1, 1000]; b.steps >= 1; b.idle_s > 0.
/// @returns the exit status: 0 when every run converged with no invariant violation, 1 if not.
int run_scale_bench(const ScaleBench& b);

}  // namespace quiver::tools::bench
