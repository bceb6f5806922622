// The replicator's peer table (peer_table.h).

#include "quiver/agents/replica/replication/peer_table.h"

namespace quiver::agents::inline replica {

std::size_t PeerTable::lower(const PeerId& id) const {
  auto it = std::lower_bound(order_.begin(), order_.end(), id,
                             [this](std::uint16_t slot, const PeerId& key) { return slots_[slot].id < key; });
  return static_cast<std::size_t>(it - order_.begin());
}

PeerTable::iterator PeerTable::upper_bound(const PeerId& id) {
  const std::size_t i = lower(id);
  return {this, has_at(i, id) ? i + 1 : i};
}

PeerRecord& PeerTable::operator[](const PeerId& id) {
  auto [it, added] = try_emplace(id);
  if (it == end()) {
    spare_ = PeerRecord{};
    spare_.id = id;
    return spare_;
  }
  return it->second;
}

std::pair<PeerTable::iterator, bool> PeerTable::try_emplace(const PeerId& id) {
  const std::size_t i = lower(id);
  if (has_at(i, id)) return {iterator{this, i}, false};
  if (order_.size() >= kMaxPeers) return {end(), false};
  std::uint16_t slot;
  if (!free_.empty()) {
    slot = free_.back();
    free_.pop_back();
  } else {
    slot = static_cast<std::uint16_t>(slots_.size());
    slots_.emplace_back();
  }
  slots_[slot] = PeerRecord{};
  slots_[slot].id = id;
  order_.insert(order_.begin() + static_cast<std::ptrdiff_t>(i), slot);
  return {iterator{this, i}, true};
}

PeerTable::iterator PeerTable::erase(iterator it) {
  const std::size_t i = it.index();
  const std::uint16_t slot = order_[i];
  details_.erase(slots_[slot].id);
  slots_[slot] = PeerRecord{};
  free_.push_back(slot);
  order_.erase(order_.begin() + static_cast<std::ptrdiff_t>(i));
  return {this, i};
}

PeerDetail& PeerTable::detail(const PeerRecord& p, std::int64_t now_ns) {
  PeerDetail& d = details_[p.id];
  d.used_ns = now_ns;
  return d;
}

const PeerDetail& PeerTable::seen(const PeerRecord& p) const {
  static const PeerDetail kNone;
  auto it = details_.find(p.id);
  return it == details_.end() ? kNone : it->second;
}

std::size_t PeerTable::memory_bytes() const {
  // A deque holds its records in blocks of 512 bytes (libstdc++), and a map of block pointers.
  constexpr std::size_t kBlock = 512, kPerBlock = kBlock / sizeof(PeerRecord);
  const std::size_t blocks = (slots_.size() + kPerBlock - 1) / kPerBlock;
  std::size_t n = blocks * (kBlock + sizeof(void*)) + order_.capacity() * sizeof(order_[0]) +
                  free_.capacity() * sizeof(free_[0]);
  constexpr std::size_t kNode = 48;  // a std::map node's own cost, beyond its key and value
  for (const auto& [id, d] : details_) {
    n += kNode + sizeof(id) + sizeof(d) + (d.name.capacity() > 15 ? d.name.capacity() : 0) +
         d.applied.memory_bytes() + d.holds.capacity() * sizeof(PeerDetail::Held);
  }
  return n;
}

static_assert(sizeof(PeerRecord) == 32, "a peer's record stays 32 bytes (docs/protocol.md)");

}  // namespace quiver::agents
