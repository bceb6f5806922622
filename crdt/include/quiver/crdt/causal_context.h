#pragma once
/// @file
/// The causal context of a delta-state CRDT: the set of every dot a replica has seen, kept as a
/// compact version vector plus a "dot cloud" of ranges beyond it.

#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "quiver/crdt/dot.h"
#include "quiver/base/hash.h"

namespace quiver::crdt {

/// A set of dots. Per replica: every counter in [1, max] plus disjoint ranges above max+1.
/// Adding a dot or a range is O(log k) for k ranges of that replica, compaction included
/// (ranges that become contiguous with the version vector are absorbed as they are reached).
class CausalContext {
 public:
  struct Range {
    std::uint64_t lo;
    std::uint64_t hi;  // inclusive
  };

  bool contains(const Dot& d) const { return contains(d.replica, d.counter); }
  bool contains(const ReplicaId& r, std::uint64_t counter) const;
  void add(const Dot& d) { add_range(d.replica, d.counter, d.counter); }
  /// Adds every counter in [lo, hi]; lo >= 1, lo <= hi.
  void add_range(const ReplicaId& r, std::uint64_t lo, std::uint64_t hi);
  /// Set union.
  void join(const CausalContext& other);
  /// True if every dot of `other` is in this context.
  bool includes(const CausalContext& other) const;
  /// True if every counter of `r` in [lo, hi] is present (lo <= hi).
  bool includes(const ReplicaId& r, std::uint64_t lo, std::uint64_t hi) const;
  /// True if some counter of `r` in [lo, hi] is present (lo <= hi).
  bool intersects(const ReplicaId& r, std::uint64_t lo, std::uint64_t hi) const;
  /// Dots of this context that `other` lacks.
  CausalContext minus(const CausalContext& other) const;

  /// The compact version-vector entry: every counter in [1, n] is present.
  std::uint64_t contiguous(const ReplicaId& r) const;
  /// The highest counter of `r` present (0 if none).
  std::uint64_t max_counter(const ReplicaId& r) const;
  /// The highest counter of any replica (0 if empty): the Lamport clock of this context.
  std::uint64_t max_counter_overall() const { return max_overall_; }

  bool empty() const { return replicas_.empty(); }
  std::size_t replica_count() const { return replicas_.size(); }
  /// Number of ranges (version-vector entries count as one each): a size measure.
  std::size_t range_count() const;
  /// Number of dots (may be huge; for tests).
  std::uint64_t dot_count() const;
  void clear() {
    replicas_.clear();
    max_overall_ = 0;
  }

  /// Calls f(replica, lo, hi) for every maximal range, replicas in ascending order, ranges
  /// ascending. Canonical: equal sets give equal call sequences.
  template <class F>
  void for_each_range(F&& f) const {
    for (const auto& [r, e] : replicas_) {
      if (e.max > 0) f(r, std::uint64_t{1}, e.max);
      for (const auto& [lo, hi] : e.cloud) f(r, lo, hi);
    }
  }
  /// Replicas present, ascending.
  std::vector<ReplicaId> replicas() const;

  Digest128 digest() const;
  friend bool operator==(const CausalContext& a, const CausalContext& b);

 private:
  struct Entry {
    std::uint64_t max = 0;                     // [1, max] present
    std::map<std::uint64_t, std::uint64_t> cloud;  // lo -> hi, disjoint, lo > max + 1
  };
  Entry* find(const ReplicaId& r);
  const Entry* find(const ReplicaId& r) const;
  Entry& find_or_add(const ReplicaId& r);

  std::vector<std::pair<ReplicaId, Entry>> replicas_;  // sorted by replica
  std::uint64_t max_overall_ = 0;
};

}  // namespace quiver::crdt
