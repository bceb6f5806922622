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

bool CausalContext::contains(const ReplicaId& r, std::uint64_t counter) const {
  const std::uint64_t* max = find(r);
  if (max == nullptr || counter == 0) return false;
  if (counter <= *max) return true;
  const Cloud* c = cloud(r);
  if (c == nullptr) return false;
  auto it = c->upper_bound(counter);
  if (it == c->begin()) return false;
  --it;
  return counter <= it->second;
}

void CausalContext::add_range(const ReplicaId& r, std::uint64_t lo, std::uint64_t hi) {
  // All comparisons are written as "x - 1 <= y" rather than "x <= y + 1": counters go up to
  // 2^64 - 1 and y + 1 would wrap.
  if (lo == 0) lo = 1;
  if (hi < lo) return;
  max_overall_ = std::max(max_overall_, hi);
  std::uint64_t& max = find_or_add(r);
  if (hi <= max) return;
  if (lo - 1 <= max) {
    max = hi;
    // Absorb cloud ranges that the version vector has reached.
    if (clouds_.empty()) return;
    auto c = clouds_.find(r);
    if (c == clouds_.end()) return;
    auto it = c->second.begin();
    while (it != c->second.end() && it->first - 1 <= max) {
      max = std::max(max, it->second);
      it = c->second.erase(it);
    }
    if (c->second.empty()) clouds_.erase(c);
    return;
  }
  // Insert [lo, hi] into the cloud, merging with overlapping or adjacent ranges.
  Cloud& cloud = clouds_[r];
  auto it = cloud.upper_bound(lo);
  if (it != cloud.begin()) {
    auto prev = std::prev(it);
    if (prev->second >= lo - 1) {
      if (prev->second >= hi) return;
      lo = prev->first;
      it = prev;
    }
  }
  while (it != cloud.end() && it->first - 1 <= hi) {
    hi = std::max(hi, it->second);
    it = cloud.erase(it);
  }
  cloud.emplace(lo, hi);
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
  const Cloud* c = cloud(r);
  if (c == nullptr) return false;
  const std::uint64_t from = std::max(lo, *max + 1);
  auto it = c->upper_bound(from);
  if (it == c->begin()) return false;
  --it;
  return it->first <= from && hi <= it->second;
}

bool CausalContext::intersects(const ReplicaId& r, std::uint64_t lo, std::uint64_t hi) const {
  const std::uint64_t* max = find(r);
  if (max == nullptr) return false;
  if (lo <= *max) return true;
  const Cloud* c = cloud(r);
  if (c == nullptr) return false;
  auto it = c->upper_bound(hi);  // the first range starting beyond hi
  if (it == c->begin()) return false;
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
    const std::uint64_t* max = other.find(r);
    if (max == nullptr) {
      out.add_range(r, lo, hi);
      return;
    }
    std::uint64_t cur = std::max(lo, *max + 1);
    if (cur > hi) return;
    static const Cloud kNone;
    const Cloud* c = other.cloud(r);
    const Cloud& cl = c ? *c : kNone;
    // Walk the other side's cloud ranges that intersect [cur, hi].
    auto it = cl.upper_bound(cur);
    if (it != cl.begin()) {
      auto prev = std::prev(it);
      if (prev->second >= cur) {
        if (prev->second >= hi) return;  // covered to the end (also avoids wrapping at 2^64 - 1)
        cur = prev->second + 1;
      }
    }
    while (cur <= hi) {
      if (it == cl.end() || it->first > hi) {
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
  const std::uint64_t* max = find(r);
  return max ? *max : 0;
}

std::uint64_t CausalContext::max_counter(const ReplicaId& r) const {
  const std::uint64_t* max = find(r);
  if (max == nullptr) return 0;
  const Cloud* c = cloud(r);
  return c == nullptr ? *max : c->rbegin()->second;
}

std::size_t CausalContext::range_count() const {
  std::size_t n = 0;
  for (const auto& [r, max] : replicas_) n += max > 0 ? 1 : 0;
  for (const auto& [r, c] : clouds_) n += c.size();
  return n;
}

std::size_t CausalContext::memory_bytes() const {
  // A std::map node: its value plus about 48 bytes (links, colour, allocator overhead).
  constexpr std::size_t kNode = 48;
  std::size_t n = replicas_.capacity() * sizeof(replicas_[0]);
  for (const auto& [r, c] : clouds_) n += kNode + sizeof(r) + sizeof(c) + c.size() * (kNode + 16);
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
  return a.replicas_ == b.replicas_ && a.clouds_ == b.clouds_;
}

}  // namespace quiver::crdt
