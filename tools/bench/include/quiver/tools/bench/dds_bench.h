#pragma once
// The DDS transport benchmark (`quiver bench dds`): one writer and K reader processes on
// loopback, then a late joiner; throughput, one-way latency and join time.

#include "quiver/tools/bench/role_processes.h"

namespace quiver::tools::bench {

struct DdsBench {
  RoleCommand roles;                ///< how the writer, reader and joiner processes start
  long updates = 1'000'000;         ///< random writes of the throughput phase
  int batch = 100;                  ///< writes per transaction
  int readers = 1;                  ///< reader processes
  int latency_samples = 2000;       ///< single writes of the latency phase
  int join_nodes = 10000;           ///< nodes of the graph the late joiner syncs
  bool with_viewer = false;         ///< run `quiver view` on the domain (AttachedViewer) meanwhile
  bool viewer_every_delta = false;  ///< the viewer reads every delta
  /// DDS Security and signed, policy-checked deltas: every role gets an identity from a fresh CA
  /// in a temporary directory (docs/security.md).
  bool secure = false;
  /// DDS Security alone: as `secure` but without signed deltas and graph-level permissions.
  bool secure_transport = false;
  /// Marks each latency sample's stages in the writer and the readers (base/stage_marks.h) and
  /// reports their medians (`stages_us_p50`).
  bool stages = false;
};

/// Runs the benchmark: the readers, the writer (throughput, then latency, then the join graph),
/// then the joiner, phases coordinated in-band through a control node of the replicated graph;
/// all processes share CLOCK_MONOTONIC, so one-way latencies are measured directly. Prints one
/// JSON line on stdout.
/// @pre the counts are within the ranges of `quiver bench dds`'s options; not `with_viewer`
/// together with `secure` or `secure_transport` (refused with status 2).
/// @returns the exit status: 0 when the joiner synced, 1 when it did not or a role gave no
/// result, 2 when the processes or the keys cannot be made.
int run_dds_bench(const DdsBench& b);

}  // namespace quiver::tools::bench
