// Replicator relay buffer: the deltas kept to answer pulls, bounded in bytes, and dropped once
// every live peer holds them.

#include "quiver/agents/replica/replication/replicator.h"

#include <algorithm>

namespace quiver::agents::inline replica {

void Replicator::remember(const PeerId& origin, std::uint64_t lo, std::uint64_t hi, std::uint64_t digest, Bytes bytes,
                          Bytes signature) {
  auto& idx = buffer_index_[origin];
  if (idx.count(lo)) return;
  buffer_bytes_ += bytes->size();
  buffer_.push_back(Buffered{origin, lo, hi, now_, std::move(bytes), std::move(signature), digest, {}});
  idx.emplace(lo, std::prev(buffer_.end()));
  while (buffer_bytes_ > opt_.buffer_bytes && buffer_.size() > 1) {
    evict_front();
    ++stats_.buffer_evictions;
  }
}

void Replicator::evict_front() { erase_buffered(buffer_.begin()); }

std::list<Replicator::Buffered>::iterator Replicator::erase_buffered(std::list<Buffered>::iterator it) {
  buffer_bytes_ -= it->bytes->size();
  auto idx = buffer_index_.find(it->origin);
  idx->second.erase(it->lo);
  if (idx->second.empty()) buffer_index_.erase(idx);
  return buffer_.erase(it);
}

void Replicator::trim_buffer() {
  // Drop what every live peer already holds: acknowledged by their summaries. No allocation per
  // entry, so a large buffer does not stall the thread.
  if (live_peer_count() == 0) return;
  for (auto it = buffer_.begin(); it != buffer_.end();) {
    if (!all_peers_hold(it->origin, it->lo, it->hi)) {
      ++it;
      continue;
    }
    it = erase_buffered(it);
  }
}

}  // namespace quiver::agents
