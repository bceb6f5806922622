#pragma once
// The scaling benchmark (`quiver bench scale`): what each agent pays as the number of agents
// grows, in the simulator (the samples DDS would carry), one JSON line per number of agents.

#include <cstdint>
#include <vector>

namespace quiver::tools::bench {

struct ScaleBench {
  std::vector<int> agents = {4, 8, 16, 32, 64, 128};  ///< the numbers of agents, in order
  int steps = 1000;        ///< workload steps (one random agent commits per step)
  std::uint64_t seed = 5;  ///< of the workload; one run per number of agents, all with it
  double idle_s = 1.0;     ///< virtual seconds of idle time after each run, measured apart
};

/// For each number of agents N, the run of `quiver sim --agents N --steps S --seed SEED` (no
/// faults, the default workload and heartbeat period): one JSON line on stdout with its ops,
/// bytes and messages, bytes and messages per op per agent, the idle traffic per second per agent
/// (`idle_s` of virtual time after the run converged, with nothing to replicate), whether it
/// converged, and the run's wall time. scripts/plot_scale.py draws the lines as log-log curves.
/// @pre every entry of `b.agents` is in [1, 256]; b.steps >= 1; b.idle_s > 0.
/// @returns the exit status: 0 when every run converged with no invariant violation, 1 if not.
int run_scale_bench(const ScaleBench& b);

}  // namespace quiver::tools::bench
