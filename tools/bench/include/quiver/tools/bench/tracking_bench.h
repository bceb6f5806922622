#pragma once
// The human-tracking DDS benchmark (`quiver bench dds-tracking`): the AGM paper's load (2 people
// x 15 joints x 30 Hz) from one tracker process to N-1 listener processes.

#include "quiver/tools/bench/role_processes.h"

namespace quiver::tools::bench {

struct TrackingBench {
  RoleCommand roles;                ///< how the tracker and listener processes start
  int agents = 20;                  ///< the tracker and agents-1 listeners
  double seconds = 5;               ///< how long the tracker writes
  bool with_viewer = false;         ///< run `quiver view` on the domain (AttachedViewer) meanwhile
  bool viewer_every_delta = false;  ///< the viewer reads every delta
};

/// Runs the listeners, then the tracker for `seconds`, and prints one JSON line on stdout: RT
/// updates per second, deliveries, latency p50/p99/max.
/// @pre b.agents >= 2, b.seconds > 0.
/// @returns the exit status: 0, 1 when a role gave no result, 2 when the processes cannot be
/// started.
int run_tracking_bench(const TrackingBench& b);

}  // namespace quiver::tools::bench
