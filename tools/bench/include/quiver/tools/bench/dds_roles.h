#pragma once
// The roles of the DDS benchmarks, each one process joining the domain (`quiver bench-dds-role
// ROLE`): writer, reader and joiner for `bench dds`, tracker and listener for `bench
// dds-tracking`. Each prints one JSON line of its results on stdout.

#include <functional>
#include <memory>
#include <string>

#include "quiver/agents/runtime/process/dds_replica.h"
#include "quiver/base/result.h"

namespace quiver::tools::bench {

/// Opens a role's replica on the benchmark's domain (the caller's DDS flags: configuration,
/// security); the role sets its name and DDS options.
using ReplicaFactory =
    std::function<Result<std::unique_ptr<agents::DdsReplica>>(agents::DdsReplicaOptions)>;

/// One role process of a DDS benchmark. The coordinators (dds_bench.h, tracking_bench.h) pass the
/// counts as command-line options; the defaults are theirs.
struct DdsRole {
  /// writer, reader, joiner (`bench dds`), tracker or listener (`bench dds-tracking`).
  std::string role;
  ReplicaFactory open;         ///< opens this role's replica
  int id = 0;                  ///< reader and listener: which one
  int readers = 1;             ///< writer: readers to wait for
  long updates = 1'000'000;    ///< writer: random writes of the throughput phase
  int batch = 100;             ///< writer: writes per transaction
  int latency_samples = 2000;  ///< writer: single writes of the latency phase
  int join_nodes = 10000;      ///< writer, joiner: nodes of the graph the joiner syncs
  int agents = 20;             ///< tracker: itself and the listeners to wait for
  double seconds = 5;          ///< tracker: how long it writes; listener: how long to wait
  bool stages = false;         ///< writer, reader: mark each latency sample's stages (stage_marks.h)
};

/// Runs `r.role` until its phase of the benchmark ends, and prints its JSON result line.
/// @pre r.open is set.
/// @returns the exit status: 0; 1 when the writer's readers did not appear; 2 when the replica
/// cannot be opened or the role is unknown.
int run_dds_role(const DdsRole& r);

}  // namespace quiver::tools::bench
