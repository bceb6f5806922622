// The causal context of a delta-state CRDT: every dot a replica has seen, as a version vector plus a cloud of
// ranges beyond it.
#include "quiver/crdt/causal_context.h"

#include <algorithm>
#include <cinttypes>
#include <cstdio>

namespace quiver::crdt {

std::string ReplicaId::to_string() const {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%016" PRIx64 ".%" PRIu64, agent, incarnation);
  return buf;
}

std::string Dot::to_string() const { return replica.to_string() + ":" + std::to_string(counter); }

CausalContext::Entry* CausalContext::find(const ReplicaId& r) {
  auto it = std::lower_bound(replicas_.begin(), replicas_.end(), r,
                             [](const auto& p, const ReplicaId& key) { return p.first < key; });
  return (it != replicas_.end() && it->first == r) ? &it->second : nullptr;
}

const CausalContext::Entry* CausalContext::find(const ReplicaId& r) const {
  return const_cast<CausalContext*>(this)->find(r);
}

CausalContext::Entry& CausalContext::find_or_add(const ReplicaId& r) {
  auto it = std::lower_bound(replicas_.begin(), replicas_.end(), r,
                             [](const auto& p, const ReplicaId& key) { return p.first < key; });
  if (it != replicas_.end() && it->first == r) return it->second;
  return replicas_.insert(it, {r, Entry{}})->second;
}

bool CausalContext::contains(const ReplicaId& r, std::uint64_t counter) const {
  const Entry* e = find(r);
  if (e == nullptr || counter == 0) return false;
  if (counter <= e->max) return true;
  auto it = e->cloud.upper_bound(counter);
  if (it == e->cloud.begin()) return false;
  --it;
  return counter <= it->second;
}

void CausalContext::add_range(const ReplicaId& r, std::uint64_t lo, std::uint64_t hi) {
  // All comparisons are written as "x - 1 <= y" rather than "x <= y + 1": counters go up to
  // 2^64 - 1 and y + 1 would wrap.
  if (lo == 0) lo = 1;
  if (hi < lo) return;
  max_overall_ = std::max(max_overall_, hi);
  Entry& e = find_or_add(r);
  if (hi <= e.max) return;
  if (lo - 1 <= e.max) {
    e.max = hi;
    // Absorb cloud ranges that the version vector has reached.
    auto it = e.cloud.begin();
    while (it != e.cloud.end() && it->first - 1 <= e.max) {
      e.max = std::max(e.max, it->second);
      it = e.cloud.erase(it);
    }
    return;
  }
  // Insert [lo, hi] into the cloud, merging with overlapping or adjacent ranges.
  auto it = e.cloud.upper_bound(lo);
  if (it != e.cloud.begin()) {
    auto prev = std::prev(it);
    if (prev->second >= lo - 1) {
      if (prev->second >= hi) return;
      lo = prev->first;
      it = prev;
    }
  }
  while (it != e.cloud.end() && it->first - 1 <= hi) {
    hi = std::max(hi, it->second);
    it = e.cloud.erase(it);
  }
  e.cloud.emplace(lo, hi);
}

void CausalContext::join(const CausalContext& other) {
  other.for_each_range([this](const ReplicaId& r, std::uint64_t lo, std::uint64_t hi) {
    add_range(r, lo, hi);
  });
}

bool CausalContext::includes(const ReplicaId& r, std::uint64_t lo, std::uint64_t hi) const {
  const Entry* e = find(r);
  if (e == nullptr) return false;
  if (hi <= e->max) return true;
  const std::uint64_t from = std::max(lo, e->max + 1);
  auto it = e->cloud.upper_bound(from);
  if (it == e->cloud.begin()) return false;
  --it;
  return it->first <= from && hi <= it->second;
}

bool CausalContext::intersects(const ReplicaId& r, std::uint64_t lo, std::uint64_t hi) const {
  const Entry* e = find(r);
  if (e == nullptr) return false;
  if (lo <= e->max) return true;
  auto it = e->cloud.upper_bound(hi);  // the first range starting beyond hi
  if (it == e->cloud.begin()) return false;
  --it;
  return it->second >= lo;
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
    const Entry* e = other.find(r);
    if (e == nullptr) {
      out.add_range(r, lo, hi);
      return;
    }
    std::uint64_t cur = std::max(lo, e->max + 1);
    if (cur > hi) return;
    // Walk the other side's cloud ranges that intersect [cur, hi].
    auto it = e->cloud.upper_bound(cur);
    if (it != e->cloud.begin()) {
      auto prev = std::prev(it);
      if (prev->second >= cur) {
        if (prev->second >= hi) return;  // covered to the end (also avoids wrapping at 2^64 - 1)
        cur = prev->second + 1;
      }
    }
    while (cur <= hi) {
      if (it == e->cloud.end() || it->first > hi) {
        out.add_range(r, cur, hi);
        break;
      }
      if (it->first > cur) out.add_range(r, cur, it->first - 1);
      if (it->second >= hi) break;  // covered to the end (also avoids wrapping at 2^64 - 1)
      cur = it->second + 1;
      ++it;
    }
  });
  return out;
}

std::uint64_t CausalContext::contiguous(const ReplicaId& r) const {
  const Entry* e = find(r);
  return e ? e->max : 0;
}

std::uint64_t CausalContext::max_counter(const ReplicaId& r) const {
  const Entry* e = find(r);
  if (e == nullptr) return 0;
  return e->cloud.empty() ? e->max : e->cloud.rbegin()->second;
}

std::size_t CausalContext::range_count() const {
  std::size_t n = 0;
  for (const auto& [r, e] : replicas_) n += (e.max > 0 ? 1 : 0) + e.cloud.size();
  return n;
}

std::uint64_t CausalContext::dot_count() const {
  std::uint64_t n = 0;
  for_each_range([&](const ReplicaId&, std::uint64_t lo, std::uint64_t hi) { n += hi - lo + 1; });
  return n;
}

std::vector<ReplicaId> CausalContext::replicas() const {
  std::vector<ReplicaId> out;
  out.reserve(replicas_.size());
  for (const auto& [r, e] : replicas_) out.push_back(r);
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
  if (a.replicas_.size() != b.replicas_.size()) return false;
  for (std::size_t i = 0; i < a.replicas_.size(); ++i) {
    const auto& [ra, ea] = a.replicas_[i];
    const auto& [rb, eb] = b.replicas_[i];
    if (ra != rb || ea.max != eb.max || ea.cloud != eb.cloud) return false;
  }
  return true;
}

}  // namespace quiver::crdt
