#pragma once
/// @file
/// The causal context of a delta-state CRDT: the set of every dot a replica has seen, kept as a
/// compact version vector plus a "dot cloud" of ranges beyond it.
///
/// Threading: a plain value type without synchronization: const members may run concurrently
/// on one object, a mutation needs exclusive access. Nothing here throws (but std::bad_alloc).

#include <cstdint>
#include <utility>
#include <vector>

#include "quiver/crdt/dot.h"
#include "quiver/base/hash.h"

namespace quiver::crdt {

/// A set of dots. Per replica: every counter in [1, max] plus disjoint ranges above max+1.
/// Both kinds live in sorted flat arrays: a lookup is O(log k); adding a range at the end (as
/// decoding and joining do, in ascending order) is amortized O(1), and elsewhere O(k) for k
/// ranges in all. clear() keeps the arrays' capacity, so a context reused for one delta after
/// another allocates nothing once it has grown.
class CausalContext {
 public:
  struct Range {
    std::uint64_t lo;
    std::uint64_t hi;  // inclusive
  };

  /// @returns true if dot `d` is in the context (never for a null dot: counter 0).
  bool contains(const Dot& d) const { return contains(d.replica, d.counter); }
  /// @returns true if counter `counter` of replica `r` is in the context (false for 0).
  bool contains(const ReplicaId& r, std::uint64_t counter) const;
  /// Adds dot `d` (a null dot adds nothing).
  void add(const Dot& d) { add_range(d.replica, d.counter, d.counter); }
  /// Adds every counter in [lo, hi]; lo >= 1, lo <= hi.
  /// A lo of 0 is read as 1; an empty range (hi < lo) adds nothing.
  void add_range(const ReplicaId& r, std::uint64_t lo, std::uint64_t hi);
  /// Set union.
  void join(const CausalContext& other);
  /// True if every dot of `other` is in this context.
  /// @returns true for an empty `other`.
  bool includes(const CausalContext& other) const;
  /// True if every counter of `r` in [lo, hi] is present (lo <= hi).
  /// @pre 1 <= lo <= hi.
  bool includes(const ReplicaId& r, std::uint64_t lo, std::uint64_t hi) const;
  /// True if some counter of `r` in [lo, hi] is present (lo <= hi).
  /// @pre 1 <= lo <= hi.
  bool intersects(const ReplicaId& r, std::uint64_t lo, std::uint64_t hi) const;
  /// Dots of this context that `other` lacks.
  /// @returns a new context (set difference this \ other).
  CausalContext minus(const CausalContext& other) const;

  /// The compact version-vector entry: every counter in [1, n] is present.
  /// @returns n (0 if counter 1 of `r` is absent).
  std::uint64_t contiguous(const ReplicaId& r) const;
  /// The highest counter of `r` present (0 if none).
  /// @returns that counter; counters below it may be missing (see contiguous()).
  std::uint64_t max_counter(const ReplicaId& r) const;
  /// The highest counter of any replica (0 if empty): the Lamport clock of this context.
  /// @returns the highest counter ever added; clear() resets it, minus() results compute their
  ///          own.
  std::uint64_t max_counter_overall() const { return max_overall_; }

  /// @returns true if the context holds no dot.
  bool empty() const { return replicas_.empty(); }
  /// @returns the number of replicas with at least one dot.
  std::size_t replica_count() const { return replicas_.size(); }
  /// Number of ranges (version-vector entries count as one each): a size measure.
  /// @returns the number of calls for_each_range() makes.
  std::size_t range_count() const;
  /// Number of dots (may be huge; for tests).
  /// @returns the sum of the ranges' lengths (modulo 2^64).
  std::uint64_t dot_count() const;
  /// Removes every dot (keeping the arrays' capacity); max_counter_overall() becomes 0.
  void clear() {
    replicas_.clear();
    cloud_.clear();
    max_overall_ = 0;
  }

  /// Calls f(replica, lo, hi) for every maximal range, replicas in ascending order, ranges
  /// ascending. Canonical: equal sets give equal call sequences.
  /// @pre `f` does not modify this context.
  template <class F>
  void for_each_range(F&& f) const {
    auto c = cloud_.begin();
    for (const auto& [r, max] : replicas_) {
      if (max > 0) f(r, std::uint64_t{1}, max);
      for (; c != cloud_.end() && c->replica == r; ++c) f(r, c->lo, c->hi);
    }
  }
  /// Bytes this context holds (its arrays' capacity): a replica costs 24 bytes while its dots
  /// are contiguous, and each range beyond 32 more.
  std::size_t memory_bytes() const;
  /// Gives back memory: when the replicas' array has room for more than `entries` (at least as
  /// many as it holds), it is reallocated to hold that many. O(replicas).
  void shrink_to(std::size_t entries);
  /// Replicas present, ascending.
  /// @returns the replicas with at least one dot, in ReplicaId order.
  std::vector<ReplicaId> replicas() const;

  /// @returns a canonical digest of the set: equal sets give equal digests (in every process).
  Digest128 digest() const;
  /// @returns true if both hold the same dots (max_counter_overall() is not compared).
  friend bool operator==(const CausalContext& a, const CausalContext& b);

 private:
  // A range beyond its replica's version-vector entry: lo > max + 1, disjoint from and not
  // adjacent to the replica's other ranges. Kept apart from the entries (a gap is rare and brief)
  // so that a replica whose dots are contiguous costs its id and one counter.
  struct CloudRange {
    ReplicaId replica;
    std::uint64_t lo, hi;
    bool operator==(const CloudRange&) const = default;
  };
  using CloudIt = std::vector<CloudRange>::const_iterator;
  std::uint64_t* find(const ReplicaId& r);
  const std::uint64_t* find(const ReplicaId& r) const;
  std::uint64_t& find_or_add(const ReplicaId& r);
  /// The ranges of `r` beyond its entry, ascending: [first, second) of cloud_.
  std::pair<CloudIt, CloudIt> cloud(const ReplicaId& r) const;

  std::vector<std::pair<ReplicaId, std::uint64_t>> replicas_;  // sorted by replica: [1, max] present
  std::vector<CloudRange> cloud_;                               // sorted by (replica, lo)
  std::uint64_t max_overall_ = 0;
};

}  // namespace quiver::crdt
