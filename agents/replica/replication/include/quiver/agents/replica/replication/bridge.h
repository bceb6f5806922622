#pragma once
/// @file
/// A bridge between two replicas of one process that serve different groups of peers: a robot
/// team's gateway holds one replica in its robot's domain and one in the team's, and the bridge
/// carries every change either joins to the other (docs/teams.md). A delta crosses unchanged
/// (origin, sequence interval, payload, signature), so each group deduplicates and checks it as
/// if it came from its origin; a state transfer crosses as the state one side holds beyond the
/// other. Nothing crosses back: what a side joins from the bridge is not carried again.
/// Each side is a gateway replica (ReplicatorOptions::gateway) that vouches for the other side's
/// peers: it answers a hold query only as far as they all hold the origin, and tells its own peers
/// which replicas are alive over there, so that locks hold across robots.
///
/// Threading: both replicators and this bridge belong to one owner thread.

#include <cstdint>
#include <vector>

#include "quiver/agents/replica/replication/replicator.h"

namespace quiver::agents::inline replica {

class ReplicaBridge {
 public:
  struct Stats {
    std::uint64_t deltas_to[2] = {0, 0};  ///< deltas relayed into side 0 (a) and side 1 (b), new there
    std::uint64_t states_to[2] = {0, 0};  ///< states adopted by each side
  };
  /// Installs itself as both replicators' on_joined() callback. @pre `a` and `b` outlive the
  /// bridge, serve different graphs and belong to the calling thread.
  ReplicaBridge(Replicator& a, Replicator& b, std::int64_t check_ns = 500'000'000);
  /// Removes the callbacks.
  ~ReplicaBridge();
  ReplicaBridge(const ReplicaBridge&) = delete;
  ReplicaBridge& operator=(const ReplicaBridge&) = delete;

  /// Tells each side's peers who is alive on the other side (when that changed), carries what
  /// each side joined since the last call to the other side, and answers hold queries that wait
  /// on what the other side's peers said since. After a state
  /// transfer on one side, and every `check_ns` while the two (origin, seq) sets differ, the side
  /// that lacks something adopts what the other holds beyond it. Call it after each round of
  /// either replica, outside any join. Owner thread only.
  void pump(std::int64_t now_ns);
  /// True when both sides hold the same (origin, seq) set. Owner thread only.
  bool even() const;
  const Stats& stats() const { return stats_; }

 private:
  void joined(int side, const DeltaMsg* m);
  void adopt(int from, int to);

  Replicator* r_[2];
  std::vector<DeltaMsg> out_[2];  // joined on side i, to be relayed into the other
  std::vector<PeerId> holds_[2];  // origins side i's askers may now be answered about
  bool state_joined_[2] = {false, false};
  int relaying_into_ = -1;  // the side being fed: what it joins now came from the bridge
  std::int64_t check_ns_;
  std::int64_t next_check_ns_ = 0;
  Stats stats_;
};

}  // namespace quiver::agents
