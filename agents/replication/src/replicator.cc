#include "quiver/agents/replication/replicator.h"

#include <algorithm>

#include "quiver/agents/replication/frame_codec.h"
#include "quiver/graph/codec.h"

namespace quiver::agents {
namespace {
constexpr std::uint64_t kMaxInterval = 1u << 20;  // commits coalesced into one delta interval
}

Replicator::Replicator(graph::Graph& g, Transport& t, ReplicatorOptions options)
    : g_(g), t_(t), opt_(std::move(options)), self_(g.replica()) {
  g_.set_delta_sink([this](const graph::GraphDelta& d) { on_local_delta(d); });
}

Replicator::~Replicator() { g_.set_delta_sink(nullptr); }

// ------------------------------------------------------------------ local deltas

void Replicator::on_local_delta(const graph::GraphDelta& d) {
  ++seq_;
  applied_.add(crdt::Dot{self_, seq_});
  if (opt_.coalesce) {
    if (pending_lo_ == 0) {
      pending_ = d;
      pending_lo_ = seq_;
    } else {
      pending_.append(d);
    }
    if (seq_ - pending_lo_ + 1 >= kMaxInterval) flush();  // receivers refuse longer intervals
    return;
  }
  publish(graph::encode(d), seq_, seq_);
}

void Replicator::flush() {
  if (pending_lo_ == 0) return;
  std::uint64_t lo = pending_lo_;
  publish(graph::encode(pending_), lo, seq_);
  pending_.clear();
  pending_lo_ = 0;
}

void Replicator::publish(std::vector<std::uint8_t> bytes, std::uint64_t lo, std::uint64_t hi) {
  auto shared = std::make_shared<const std::vector<std::uint8_t>>(std::move(bytes));
  applied_.add_range(self_, lo, hi);
  remember(self_, lo, hi, shared);
  ++stats_.deltas_published;
  queue(PeerId{}, DeltaMsg{self_, lo, hi, std::move(shared)});
  send_queued();
}

// ------------------------------------------------------------------ envelopes

void Replicator::queue(const PeerId& to, Message msg) { outbox_.push_back(Outgoing{to, std::move(msg)}); }

void Replicator::send_queued() {
  std::size_t i = 0;
  while (i < outbox_.size()) {
    Envelope e;
    e.from = self_;
    e.to = outbox_[i].to;
    // Batch consecutive messages to the same destination up to the frame limit.
    std::size_t bytes = 0;
    while (i < outbox_.size() && outbox_[i].to == e.to) {
      std::size_t sz = approx_size(outbox_[i].msg);
      if (!e.messages.empty() && bytes + sz > opt_.max_frame_bytes) break;
      bytes += sz;
      e.messages.push_back(std::move(outbox_[i].msg));
      ++i;
    }
    ++stats_.envelopes_sent;
    stats_.bytes_sent_estimate += bytes;
    t_.send(e);
  }
  outbox_.clear();
}

void Replicator::reject(const Error& e) {
  ++stats_.rejected_frames;
  if (error_cb_) error_cb_(e);
}

void Replicator::on_frame(std::span<const std::uint8_t> frame, std::int64_t now_ns) {
  auto e = decode_frame(frame);
  if (!e.ok()) {
    now_ = std::max(now_, now_ns);
    return reject(e.error());
  }
  on_envelope(*e, now_ns);
}

void Replicator::on_envelope(const Envelope& e, std::int64_t now_ns) {
  now_ = std::max(now_, now_ns);
  if (e.from == self_ || e.from.is_null()) return;
  if (!e.to.is_null() && !(e.to == self_)) return;
  ++stats_.envelopes_received;
  heard_from(e.from);
  for (const Message& m : e.messages) std::visit([&](const auto& msg) { handle(e.from, msg); }, m);
  if (announce_soon_) {
    announce_soon_ = false;
    send_summary();
  }
  send_queued();
}

// ------------------------------------------------------------------ membership

Replicator::Peer& Replicator::heard_from(const PeerId& from) {
  auto [it, fresh] = peers_.try_emplace(from);
  Peer& p = it->second;
  if (fresh) p.info.id = from;
  p.info.last_heard_ns = now_;
  if (!p.info.alive) {
    p.info.alive = true;
    // A new incarnation of an agent means the old one is gone.
    for (auto& [id, other] : peers_)
      if (other.info.alive && id.agent == from.agent && !(id == from) && id.incarnation < from.incarnation)
        mark_left(other);
    if (membership_cb_) membership_cb_(Membership::kJoined, p.info);
  }
  return p;
}

void Replicator::mark_left(Peer& p) {
  if (!p.info.alive) return;
  p.info.alive = false;
  reassembly_.erase(p.info.id);
  if (pulling_ && pull_target_ == p.info.id) pulling_ = false;
  if (membership_cb_) membership_cb_(Membership::kLeft, p.info);
}

void Replicator::on_peer_lost(const PeerId& peer) {
  auto it = peers_.find(peer);
  if (it != peers_.end()) mark_left(it->second);
}

std::vector<PeerInfo> Replicator::peers() const {
  std::vector<PeerInfo> out;
  for (const auto& [id, p] : peers_) out.push_back(p.info);
  return out;
}

std::size_t Replicator::live_peer_count() const {
  std::size_t n = 0;
  for (const auto& [id, p] : peers_) n += p.info.alive ? 1 : 0;
  return n;
}

bool Replicator::peer_alive(const PeerId& peer) const {
  auto it = peers_.find(peer);
  return it != peers_.end() && it->second.info.alive;
}

bool Replicator::all_peers_hold(const PeerId& origin, std::uint64_t lo, std::uint64_t hi) const {
  for (const auto& [id, p] : peers_)
    if (p.info.alive && !p.applied.includes(origin, lo, hi)) return false;
  return true;
}

bool Replicator::synced() const {
  bool any = false;
  for (const auto& [id, p] : peers_) {
    if (!p.info.alive) continue;
    any = true;
    if (behind(p)) return false;
  }
  return any && reassembly_.empty();
}

// ------------------------------------------------------------------ messages

void Replicator::send_summary() { queue(PeerId{}, SummaryMsg{opt_.name, opt_.observer, applied_}); }

void Replicator::handle(const PeerId& from, const SummaryMsg& m) {
  Peer& p = peers_[from];
  bool first = p.info.name.empty() && p.applied.empty();
  p.info.name = m.name;
  p.info.observer = m.observer;
  p.applied = m.applied;
  if (first) send_summary();  // let a newcomer learn about us without waiting a heartbeat
  if (pulling_ && pull_target_ == from && !behind(p)) {  // caught up with it: the pull is done
    pulling_ = false;
    pull_timeouts_in_a_row_ = 0;
  }
  if (!pulling_ && behind(p)) pull_from(from);
}

void Replicator::handle(const PeerId& from, const DeltaMsg& m) {
  if (m.origin == self_ || m.lo == 0 || m.hi < m.lo || !m.payload) return;
  // An interval covers the commits it joins; a huge one would mark future deltas as seen.
  if (m.hi - m.lo > kMaxInterval)
    return reject(make_error(ErrorCode::kTooLarge, "delta " + m.origin.to_string() + "#" + std::to_string(m.lo) +
                                                       " from " + from.to_string() + " claims " +
                                                       std::to_string(m.hi - m.lo + 1) + " sequence numbers"));
  if (applied_.includes(m.origin, m.lo, m.hi)) {
    ++stats_.deltas_duplicate;
    return;
  }
  Status s = graph::decode(*m.payload, scratch_);
  if (!s.ok()) {
    return reject(make_error(s.error().code, "delta " + m.origin.to_string() + "#" + std::to_string(m.lo) +
                                                 " relayed by " + from.to_string() + ": " + s.error().message));
  }
  if (!(scratch_.origin == m.origin) || scratch_.kind != graph::GraphDelta::Kind::kDelta)
    return reject(make_error(ErrorCode::kMalformed, "delta " + m.origin.to_string() + "#" + std::to_string(m.lo) +
                                                        ": the payload's origin or kind does not match"));
  g_.merge(scratch_);
  applied_.add_range(m.origin, m.lo, m.hi);
  ++stats_.deltas_applied;
  remember(m.origin, m.lo, m.hi, m.payload);
  if (applied_.contiguous(m.origin) + 1 < m.lo && !gap_pending_) {
    gap_pending_ = true;
    gap_since_ns_ = now_;
    gap_peer_ = from;
  }
}

void Replicator::pull_from(const PeerId& target) {
  pulling_ = true;
  pull_target_ = target;
  pull_sent_ns_ = now_;
  ++pull_request_;
  ++stats_.pulls_sent;
  queue(target, PullMsg{pull_request_, applied_, g_.context()});
}

void Replicator::handle(const PeerId& from, const PullMsg& m) {
  crdt::CausalContext missing = applied_.minus(m.applied);
  if (missing.empty()) {
    // Nothing to give: a summary tells the puller so, and it moves on.
    send_summary();
    return;
  }
  // Can the relay buffer cover every missing (origin, seq)?
  std::vector<const Buffered*> entries;
  bool covered = true;
  missing.for_each_range([&](const PeerId& o, std::uint64_t a, std::uint64_t b) {
    if (!covered) return;
    auto idx = buffer_index_.find(o);
    if (idx == buffer_index_.end()) {
      covered = false;
      return;
    }
    std::uint64_t cur = a;
    while (cur <= b) {
      auto it = idx->second.upper_bound(cur);
      if (it == idx->second.begin()) {
        covered = false;
        return;
      }
      --it;
      const Buffered& e = *it->second;
      if (e.hi < cur) {
        covered = false;
        return;
      }
      if (entries.empty() || entries.back() != &e) entries.push_back(&e);
      if (e.hi >= b) break;
      cur = e.hi + 1;
    }
  });
  if (covered) {
    ++stats_.pulls_answered_with_deltas;
    for (const Buffered* e : entries) {
      queue(from, DeltaMsg{e->origin, e->lo, e->hi, e->bytes});
      ++stats_.deltas_relayed;
    }
    return;
  }
  ++stats_.pulls_answered_with_state;
  std::vector<std::uint8_t> state = graph::encode(g_.state_diff(m.context));
  const std::size_t chunk = std::max<std::size_t>(opt_.chunk_bytes, 1024);
  const std::uint64_t count = std::max<std::uint64_t>(1, (state.size() + chunk - 1) / chunk);
  for (std::uint64_t i = 0; i < count; ++i) {
    StateMsg s;
    s.request = m.request;
    s.index = static_cast<std::uint32_t>(i);
    s.count = static_cast<std::uint32_t>(count);
    if (i == 0) s.applied = applied_;
    std::size_t begin = i * chunk, end = std::min(state.size(), begin + chunk);
    s.chunk = std::make_shared<const std::vector<std::uint8_t>>(state.begin() + begin, state.begin() + end);
    queue(from, std::move(s));
  }
}

void Replicator::handle(const PeerId& from, const StateMsg& m) {
  if (m.count == 0 || m.index >= m.count || !m.chunk) return;
  Reassembly& ra = reassembly_[from];
  if (ra.request != m.request || ra.count != m.count) {
    ra = Reassembly{};
    ra.request = m.request;
    ra.count = m.count;
    ra.started_ns = now_;
    ra.chunks.resize(m.count);
  }
  if (ra.chunks[m.index]) return;  // duplicate
  if (ra.bytes + m.chunk->size() > opt_.max_state_bytes) {
    reassembly_.erase(from);
    return reject(make_error(ErrorCode::kTooLarge, "state from " + from.to_string() + " exceeds max_state_bytes (" +
                                                       std::to_string(opt_.max_state_bytes) + ")"));
  }
  if (pulling_ && pull_target_ == from) pull_sent_ns_ = now_;  // progress: the pull is alive
  ra.chunks[m.index] = m.chunk;
  ++ra.received;
  ra.bytes += m.chunk->size();
  if (m.index == 0) ra.applied = m.applied;
  if (ra.received < ra.count) return;
  pull_timeouts_in_a_row_ = 0;
  std::vector<std::uint8_t> all;
  all.reserve(ra.bytes);
  for (const auto& c : ra.chunks) all.insert(all.end(), c->begin(), c->end());
  crdt::CausalContext applied = std::move(ra.applied);
  reassembly_.erase(from);
  Status s = graph::decode(all, scratch_);
  if (!s.ok()) return reject(make_error(s.error().code, "state from " + from.to_string() + ": " + s.error().message));
  if (scratch_.kind != graph::GraphDelta::Kind::kState)
    return reject(make_error(ErrorCode::kMalformed, "state from " + from.to_string() + ": not a state"));
  g_.merge(scratch_);
  applied_.join(applied);
  ++stats_.states_applied;
  stats_.state_bytes_received += all.size();
  if (pulling_ && pull_target_ == from) pulling_ = false;
  gap_pending_ = false;
}

void Replicator::handle(const PeerId& from, const ByeMsg&) { mark_left(peers_[from]); }

// ------------------------------------------------------------------ buffer

void Replicator::remember(const PeerId& origin, std::uint64_t lo, std::uint64_t hi, Bytes bytes) {
  auto& idx = buffer_index_[origin];
  if (idx.count(lo)) return;
  buffer_bytes_ += bytes->size();
  buffer_.push_back(Buffered{origin, lo, hi, std::move(bytes)});
  idx.emplace(lo, std::prev(buffer_.end()));
  while (buffer_bytes_ > opt_.buffer_bytes && buffer_.size() > 1) {
    evict_front();
    ++stats_.buffer_evictions;
  }
}

void Replicator::evict_front() {
  const Buffered& e = buffer_.front();
  buffer_bytes_ -= e.bytes->size();
  auto idx = buffer_index_.find(e.origin);
  idx->second.erase(e.lo);
  if (idx->second.empty()) buffer_index_.erase(idx);
  buffer_.pop_front();
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
    buffer_bytes_ -= it->bytes->size();
    auto idx = buffer_index_.find(it->origin);
    idx->second.erase(it->lo);
    if (idx->second.empty()) buffer_index_.erase(idx);
    it = buffer_.erase(it);
  }
}

// ------------------------------------------------------------------ timers

void Replicator::start(std::int64_t now_ns) {
  now_ = now_ns;
  started_ = true;
  next_heartbeat_ = now_ns + opt_.heartbeat_ns;
  send_summary();
  send_queued();
}

void Replicator::announce() {
  send_summary();
  send_queued();
}

void Replicator::leave() {
  flush();
  queue(PeerId{}, ByeMsg{});
  send_queued();
}

void Replicator::tick(std::int64_t now_ns) {
  now_ = std::max(now_, now_ns);
  if (opt_.coalesce) flush();
  // A pull answered by nothing for a while is retried, elsewhere if possible. The first tries
  // are impatient (a transport may lose the first answers to a newcomer while it is still
  // discovering it); patience doubles with every timeout in a row, up to pull_timeout_ns.
  const std::int64_t patience =
      std::min(opt_.pull_timeout_ns, opt_.pull_first_timeout_ns << std::min(pull_timeouts_in_a_row_, 20));
  if (pulling_ && now_ - pull_sent_ns_ > patience) {
    pulling_ = false;
    last_failed_target_ = pull_target_;
    ++stats_.pulls_timed_out;
    ++pull_timeouts_in_a_row_;
    reassembly_.erase(pull_target_);
  }
  for (auto& [id, p] : peers_)
    if (p.info.alive && now_ - p.info.last_heard_ns > opt_.lease_ns) mark_left(p);
  for (auto it = reassembly_.begin(); it != reassembly_.end();) {
    if (now_ - it->second.started_ns > 4 * opt_.pull_timeout_ns) it = reassembly_.erase(it);
    else ++it;
  }
  if (!pulling_) {
    const PeerId* pick = nullptr;
    for (const auto& [id, p] : peers_) {
      if (!p.info.alive || !behind(p)) continue;
      if (pick == nullptr || *pick == last_failed_target_) pick = &id;
    }
    if (pick) {
      pull_from(*pick);
    } else if (gap_pending_ && now_ - gap_since_ns_ >= opt_.gap_grace_ns) {
      if (peer_alive(gap_peer_)) pull_from(gap_peer_);
      gap_pending_ = false;
    }
  }
  if (started_ && now_ >= next_heartbeat_) {
    send_summary();
    trim_buffer();
    next_heartbeat_ = now_ + opt_.heartbeat_ns;
  }
  send_queued();
}

}  // namespace quiver::agents
