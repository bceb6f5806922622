#pragma once
/// @file
/// What a Replicator tells a durable store (agents/replica/store) about every change its replica joins,
/// so that the replica can be rebuilt after a crash: the store is the only implementation we
/// ship, the simulator has its own (faulty disks).
///
/// Calls come on the replicator's thread, in the order the changes were joined, after the graph
/// took them. `local` is called for each commit of this replica before its delta is published,
/// so a store that makes it durable before returning loses no change a peer could have seen.
///
/// The calls come from inside a commit or a join: implementations must not throw, nor call back
/// into the replicator or commit to its graph; a failure to persist is theirs to report.

#include <cstdint>
#include <span>

#include "quiver/crdt/causal_context.h"
#include "quiver/graph/ids.h"

namespace quiver::agents::inline replica {

class Journal {
 public:
  virtual ~Journal() = default;
  /// A commit of this replica: its delta (codec bytes, kind kDelta) under sequence number `seq`.
  /// Called inside the commit, on the replicator's thread; `delta` is valid during the call only.
  virtual void local(std::uint64_t seq, std::span<const std::uint8_t> delta) = 0;
  /// A peer's delta joined: (origin, lo..hi) and its payload as received (codec bytes).
  /// On the replicator's thread; `delta` is valid during the call only.
  virtual void remote(const graph::ReplicaId& origin, std::uint64_t lo, std::uint64_t hi,
                      std::span<const std::uint8_t> delta) = 0;
  /// A state or context diff joined (codec bytes, kind kState), with the (origin, seq) set it
  /// brought. On the replicator's thread; `fragment` is valid during the call only.
  virtual void state(std::span<const std::uint8_t> fragment, const crdt::CausalContext& applied) = 0;
  /// Sequence numbers of this replica marked used without a change (someone published under our
  /// name): a restart under the same incarnation must not reuse them. On the replicator's thread.
  /// @pre 1 <= lo <= hi.
  virtual void skipped(std::uint64_t lo, std::uint64_t hi) = 0;
};

}  // namespace quiver::agents
