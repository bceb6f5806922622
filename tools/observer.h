#pragma once
// Joining a live DDS domain as an observer and waiting until it holds the shared graph: what
// `quiver dump` and `quiver render --domain` do before they read the graph.

#include <memory>
#include <string>

#include "dds_options.h"
#include "quiver/agents/runtime/process/dds_replica.h"
#include "quiver/base/result.h"

namespace quiver::tools {

/// How an observer follows the domain.
struct ObserverMode {
  /// Writers never wait for it (a recorder; DdsConfig::best_effort_reader).
  bool best_effort = false;
  /// > 0: it reads no deltas and pulls what changed at most this often (a viewer;
  /// ReplicatorOptions::sample_ns): writers pay nothing per change for it.
  std::int64_t sample_ns = 0;
  /// When sampling: the diff bytes per second it may ask of its peers at most
  /// (ReplicatorOptions::sample_bytes_per_s; 0: no limit).
  std::size_t sample_bytes_per_s = 0;
};

/// Opens an observer replica called `name` on the domain `dds` names, without waiting for
/// anyone.
Result<std::unique_ptr<agents::DdsReplica>> open_observer(const DdsFlags& dds,
                                                          const std::string& name,
                                                          ObserverMode mode = {});

/// Waits up to `timeout_s` for a live peer, then until `r` is synced (it holds everything every
/// live peer says it holds) and stays so for 150 ms. @returns kTimeout saying which wait ended
/// ("no agent answered on DDS domain 7 within 10.0 s", "could not sync with the 2 live agents
/// within 10.0 s").
Status wait_for_graph(agents::DdsReplica& r, const DdsFlags& dds, double timeout_s);

/// Joins the domain `dds` names as an observer called `name` (open_observer()), waits for a live
/// peer, then until the replica is synced (it holds everything every live peer says it holds) and
/// stays so for 150 ms. @returns the replica, or the error of its creation, or kTimeout saying
/// which wait ended ("no agent answered on DDS domain 7 within 10.0 s", "could not sync with the 2
/// live agents within 10.0 s").
Result<std::unique_ptr<agents::DdsReplica>> join_as_observer(const DdsFlags& dds,
                                                             const std::string& name,
                                                             double timeout_s);

}  // namespace quiver::tools
