// The causal context of a delta-state CRDT: every dot a replica has seen, as a version vector plus a cloud of
// ranges beyond it.
#include "quiver/crdt/causal_context.h"

#include <algorithm>
#include <cinttypes>
#include <cstdio>

namespace quiver::crdt {

std::string ReplicaId::to_string() const {
  std::string s;
  write_to(s);
  return s;
}

void ReplicaId::write_to(std::string& out) const {
  char buf[48];
  const int n = std::snprintf(buf, sizeof buf, "%016" PRIx64 ".%" PRIu64, agent, incarnation);
  out.assign(buf, static_cast<std::size_t>(n));
}

std::string Dot::to_string() const { return replica.to_string() + ":" + std::to_string(counter); }

std::uint64_t* CausalContext::find(const ReplicaId& r) {
  auto it = std::lower_bound(replicas_.begin(), replicas_.end(), r,
                             [](const auto& p, const ReplicaId& key) { return p.first < key; });
  return (it != replicas_.end() && it->first == r) ? &it->second : nullptr;
}

const std::uint64_t* CausalContext::find(const ReplicaId& r) const {
  return const_cast<CausalContext*>(this)->find(r);
}

std::uint64_t& CausalContext::find_or_add(const ReplicaId& r) {
  auto it = std::lower_bound(replicas_.begin(), replicas_.end(), r,
                             [](const auto& p, const ReplicaId& key) { return p.first < key; });
  if (it != replicas_.end() && it->first == r) return it->second;
  return replicas_.insert(it, {r, 0})->second;
}

std::pair<CausalContext::CloudIt, CausalContext::CloudIt> CausalContext::cloud(const ReplicaId& r) const {
  if (cloud_.empty()) return {cloud_.end(), cloud_.end()};
  auto first = std::lower_bound(cloud_.begin(), cloud_.end(), r,
                                [](const CloudRange& c, const ReplicaId& key) { return c.replica < key; });
  auto last = std::upper_bound(first, cloud_.cend(), r,
                               [](const ReplicaId& key, const CloudRange& c) { return key < c.replica; });
  return {first, last};
}

namespace {
// The first range of [first, last) (ascending, disjoint) that starts beyond `counter`.
template <class It>
It starting_beyond(It first, It last, std::uint64_t counter) {
  return std::upper_bound(first, last, counter, [](std::uint64_t c, const auto& range) { return c < range.lo; });
}
}  // namespace

bool CausalContext::contains(const ReplicaId& r, std::uint64_t counter) const {
  const std::uint64_t* max = find(r);
  if (max == nullptr || counter == 0) return false;
  if (counter <= *max) return true;
  auto [first, last] = cloud(r);
  auto it = starting_beyond(first, last, counter);
  if (it == first) return false;
  --it;
  return counter <= it->hi;
}

void CausalContext::add_range(const ReplicaId& r, std::uint64_t lo, std::uint64_t hi) {
  // All comparisons are written as "x - 1 <= y" rather than "x <= y + 1": counters go up to
  // 2^64 - 1 and y + 1 would wrap.
  if (lo == 0) lo = 1;
  if (hi < lo) return;
  max_overall_ = std::max(max_overall_, hi);
  std::uint64_t& max = find_or_add(r);
  if (hi <= max) return;
  auto [cfirst, clast] = cloud(r);
  // Positions into cloud_ (erasing and inserting below keep them meaningful).
  const std::size_t first = static_cast<std::size_t>(cfirst - cloud_.cbegin());
  std::size_t last = static_cast<std::size_t>(clast - cloud_.cbegin());
  if (lo - 1 <= max) {
    max = hi;
    // Absorb cloud ranges that the version vector has reached.
    std::size_t reached = first;
    while (reached != last && cloud_[reached].lo - 1 <= max) max = std::max(max, cloud_[reached++].hi);
    cloud_.erase(cloud_.begin() + first, cloud_.begin() + reached);
    return;
  }
  // Insert [lo, hi] into the replica's ranges, merging with overlapping or adjacent ones.
  std::size_t at = static_cast<std::size_t>(
      starting_beyond(cloud_.begin() + first, cloud_.begin() + last, lo) - cloud_.begin());
  if (at != first) {
    const CloudRange& prev = cloud_[at - 1];
    if (prev.hi >= lo - 1) {
      if (prev.hi >= hi) return;
      lo = prev.lo;
      --at;
    }
  }
  std::size_t end = at;
  while (end != last && cloud_[end].lo - 1 <= hi) hi = std::max(hi, cloud_[end++].hi);
  if (end > at) {
    cloud_[at] = CloudRange{r, lo, hi};
    cloud_.erase(cloud_.begin() + at + 1, cloud_.begin() + end);
  } else {
    cloud_.insert(cloud_.begin() + at, CloudRange{r, lo, hi});
  }
}

void CausalContext::join(const CausalContext& other) {
  other.for_each_range([this](const ReplicaId& r, std::uint64_t lo, std::uint64_t hi) {
    add_range(r, lo, hi);
  });
}

bool CausalContext::includes(const ReplicaId& r, std::uint64_t lo, std::uint64_t hi) const {
  const std::uint64_t* max = find(r);
  if (max == nullptr) return false;
  if (hi <= *max) return true;
  auto [first, last] = cloud(r);
  const std::uint64_t from = std::max(lo, *max + 1);
  auto it = starting_beyond(first, last, from);
  if (it == first) return false;
  --it;
  return it->lo <= from && hi <= it->hi;
}

bool CausalContext::intersects(const ReplicaId& r, std::uint64_t lo, std::uint64_t hi) const {
  const std::uint64_t* max = find(r);
  if (max == nullptr) return false;
  if (lo <= *max) return true;
  auto [first, last] = cloud(r);
  auto it = starting_beyond(first, last, hi);
  if (it == first) return false;
  --it;
  return it->hi >= lo;
}

bool CausalContext::includes(const CausalContext& other) const {
  bool all = true;
  other.for_each_range([&](const ReplicaId& r, std::uint64_t lo, std::uint64_t hi) {
    all = all && includes(r, lo, hi);
  });
  return all;
}

CausalContext CausalContext::minus(const CausalContext& other) const {
  CausalContext out;
  for_each_range([&](const ReplicaId& r, std::uint64_t lo, std::uint64_t hi) {
    const std::uint64_t* max = other.find(r);
    if (max == nullptr) {
      out.add_range(r, lo, hi);
      return;
    }
    std::uint64_t cur = std::max(lo, *max + 1);
    if (cur > hi) return;
    // Walk the other side's cloud ranges that intersect [cur, hi].
    auto [first, last] = other.cloud(r);
    auto it = starting_beyond(first, last, cur);
    if (it != first) {
      auto prev = std::prev(it);
      if (prev->hi >= cur) {
        if (prev->hi >= hi) return;  // covered to the end (also avoids wrapping at 2^64 - 1)
        cur = prev->hi + 1;
      }
    }
    while (cur <= hi) {
      if (it == last || it->lo > hi) {
        out.add_range(r, cur, hi);
        break;
      }
      if (it->lo > cur) out.add_range(r, cur, it->lo - 1);
      if (it->hi >= hi) break;  // covered to the end (also avoids wrapping at 2^64 - 1)
      cur = it->hi + 1;
      ++it;
    }
  });
  return out;
}

std::uint64_t CausalContext::contiguous(const ReplicaId& r) const {
  const std::uint64_t* max = find(r);
  return max ? *max : 0;
}

std::uint64_t CausalContext::max_counter(const ReplicaId& r) const {
  const std::uint64_t* max = find(r);
  if (max == nullptr) return 0;
  auto [first, last] = cloud(r);
  return first == last ? *max : std::prev(last)->hi;
}

std::size_t CausalContext::range_count() const {
  std::size_t n = 0;
  for (const auto& [r, max] : replicas_) n += max > 0 ? 1 : 0;
  return n + cloud_.size();
}

std::size_t CausalContext::memory_bytes() const {
  return replicas_.capacity() * sizeof(replicas_[0]) + cloud_.capacity() * sizeof(CloudRange);
}

void CausalContext::shrink_to(std::size_t entries) {
  entries = std::max(entries, replicas_.size());
  if (replicas_.capacity() <= entries) return;
  std::vector<std::pair<ReplicaId, std::uint64_t>> kept;
  kept.reserve(entries);
  kept.assign(replicas_.begin(), replicas_.end());
  replicas_.swap(kept);
}

std::uint64_t CausalContext::dot_count() const {
  std::uint64_t n = 0;
  for_each_range([&](const ReplicaId&, std::uint64_t lo, std::uint64_t hi) { n += hi - lo + 1; });
  return n;
}

std::vector<ReplicaId> CausalContext::replicas() const {
  std::vector<ReplicaId> out;
  out.reserve(replicas_.size());
  for (const auto& [r, max] : replicas_) out.push_back(r);
  return out;
}

Digest128 CausalContext::digest() const {
  Hasher h(0xcc);
  for_each_range([&](const ReplicaId& r, std::uint64_t lo, std::uint64_t hi) {
    h.u64(r.agent).u64(r.incarnation).u64(lo).u64(hi);
  });
  return h.digest();
}

bool operator==(const CausalContext& a, const CausalContext& b) {
  return a.replicas_ == b.replicas_ && a.cloud_ == b.cloud_;
}

}  // namespace quiver::crdt
