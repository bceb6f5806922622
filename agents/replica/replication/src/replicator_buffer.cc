// Replicator relay buffer: the deltas kept to answer pulls, bounded in bytes, and dropped once
// every live peer holds them.

#include "quiver/agents/replica/replication/replicator.h"

#include <algorithm>

namespace quiver::agents::inline replica {

namespace {
// Spares kept for the next deltas: enough for a burst, not a second buffer.
constexpr std::size_t kSpareEntries = 1024, kSpareBytes = 256, kSpareCapacity = 4096, kEmptyOrigins = 64;
}  // namespace

std::shared_ptr<std::vector<std::uint8_t>> Replicator::fresh_bytes() {
  if (spare_.bytes.empty()) return std::make_shared<std::vector<std::uint8_t>>();
  auto b = std::move(spare_.bytes.back());
  spare_.bytes.pop_back();
  b->clear();
  return b;
}

void Replicator::remember(const PeerId& origin, std::uint64_t lo, std::uint64_t hi, std::uint64_t digest, Bytes bytes,
                          Bytes signature, bool ours) {
  BufferIndex& idx = buffer_index_[origin];
  if (idx.count(lo)) return;
  buffer_bytes_ += bytes->size();
  if (spare_.entries.empty()) buffer_.emplace_back();
  else buffer_.splice(buffer_.end(), spare_.entries, spare_.entries.begin());
  Buffered& b = buffer_.back();
  b.origin = origin;
  b.lo = lo;
  b.hi = hi;
  b.at_ns = now_;
  b.bytes = std::move(bytes);
  b.signature = std::move(signature);
  b.digest = digest;
  b.others.clear();
  b.ours = ours;
  if (spare_.index.empty()) {
    idx.emplace(lo, std::prev(buffer_.end()));
  } else {
    BufferIndex::node_type node = std::move(spare_.index.back());
    spare_.index.pop_back();
    node.key() = lo;
    node.mapped() = std::prev(buffer_.end());
    idx.insert(std::move(node));
  }
  while (buffer_bytes_ > opt_.buffer_bytes && buffer_.size() > 1) {
    evict_front();
    ++stats_.buffer_evictions;
  }
}

void Replicator::evict_front() { erase_buffered(buffer_.begin()); }

std::list<Replicator::Buffered>::iterator Replicator::erase_buffered(std::list<Buffered>::iterator it) {
  buffer_bytes_ -= it->bytes->size();
  auto idx = buffer_index_.find(it->origin);
  BufferIndex::node_type node = idx->second.extract(it->lo);
  if (spare_.index.size() < kSpareEntries) spare_.index.push_back(std::move(node));
  // Our own bytes no one else holds any more (the transports copy what they send) serve the next
  // delta we publish; they were made mutable by fresh_bytes().
  if (it->ours && it->bytes.use_count() == 1 && it->bytes->capacity() <= kSpareCapacity &&
      spare_.bytes.size() < kSpareBytes)
    spare_.bytes.push_back(std::const_pointer_cast<std::vector<std::uint8_t>>(std::move(it->bytes)));
  it->bytes.reset();
  it->signature.reset();
  auto next = std::next(it);
  if (spare_.entries.size() < kSpareEntries) spare_.entries.splice(spare_.entries.end(), buffer_, it);
  else buffer_.erase(it);
  return next;
}

void Replicator::forget_empty_origins() {
  if (buffer_index_.size() <= kEmptyOrigins) return;
  std::erase_if(buffer_index_, [](const auto& entry) { return entry.second.empty(); });
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
  forget_empty_origins();
}

}  // namespace quiver::agents
