#pragma once
// `quiver bench dds-scale`: N agent processes on one host over DDS (issue 22): one writes a
// change every 1/rate s, the N-1 others receive it; then all idle; then one more agent joins.

#include <vector>

#include "quiver/tools/bench/role_processes.h"

namespace quiver::tools::bench {

struct DdsScaleBench {
  RoleCommand roles;                                  ///< this executable and the DDS flags (--membership)
  std::vector<int> agents = {2, 4, 8, 16, 32, 64, 100};  ///< processes of each run, in order
  long changes = 1000;                                 ///< changes the writer makes
  double rate = 10;                                    ///< per second
  double idle_s = 10;                                  ///< idle time over which CPU is measured
  double settle_s = 2;                                 ///< the writer's wait after all joined
  int start_gap_ms = 0;                                ///< between process starts
};

/// For each N: one JSON line with the membership protocol, the time until every process saw all
/// the others (`ready_ms`), the latency from a change's commit to its arrival at each other agent
/// (p50/p99 of all deliveries, and p50/p99 of the last arrival of each change among the N-1
/// others), changes some agent never got, delivered updates per second, CPU per agent while the
/// changes flow and while idle (mean and max, % of one core), resident memory per agent, and the
/// time one more agent takes to hold everything (`join_ms`).
/// @returns 0; 1 when a run did not complete (a process gave no result, or changes went missing).
int run_dds_scale_bench(const DdsScaleBench& b);

}  // namespace quiver::tools::bench
