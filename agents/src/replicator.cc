#include "quiver/agents/replicator.h"

#include <algorithm>

#include "quiver/crdt/context_codec.h"
#include "quiver/graph/codec.h"
#include "quiver/wire.h"

namespace quiver::agents {
namespace {

constexpr std::uint8_t kMagic0 = 'Q';
constexpr std::uint8_t kMagic1 = 'R';
constexpr std::uint8_t kVersion = 1;
enum MsgType : std::uint8_t { kSummary = 1, kDelta = 2, kPull = 3, kState = 4, kBye = 5 };
constexpr std::uint64_t kMaxMessageBytes = 1ull << 30;
constexpr std::uint64_t kMaxChunks = 1u << 20;

std::vector<std::uint8_t> delta_message(const PeerId& origin, std::uint64_t lo, std::uint64_t hi,
                                        const std::vector<std::uint8_t>& bytes) {
  std::vector<std::uint8_t> msg;
  msg.reserve(bytes.size() + 32);
  wire::Writer w(msg);
  w.u8(kDelta);
  crdt::encode_replica(origin, w);
  w.varint(lo);
  w.varint(hi - lo);
  w.bytes(bytes);
  return msg;
}

}  // namespace

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
    if (pending_.empty() && pending_lo_ == 0) {
      pending_ = d;
      pending_lo_ = seq_;
    } else {
      pending_.append(d);
    }
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
  queue(PeerId{}, delta_message(self_, lo, hi, *shared));
  send_queued();
}

// ------------------------------------------------------------------ frames

void Replicator::queue(const PeerId& to, std::vector<std::uint8_t> msg) {
  outbox_.push_back(Outgoing{to, std::move(msg)});
}

void Replicator::send_queued() {
  std::size_t i = 0;
  std::vector<std::uint8_t> frame;
  while (i < outbox_.size()) {
    const PeerId to = outbox_[i].to;
    frame.clear();
    wire::Writer w(frame);
    w.u8(kMagic0);
    w.u8(kMagic1);
    w.u8(kVersion);
    crdt::encode_replica(self_, w);
    w.u8(to.is_null() ? 0 : 1);
    if (!to.is_null()) crdt::encode_replica(to, w);
    // Batch consecutive messages to the same destination up to the frame limit.
    std::size_t j = i, bytes = 0;
    while (j < outbox_.size() && outbox_[j].to == to &&
           (j == i || bytes + outbox_[j].msg.size() <= opt_.max_frame_bytes)) {
      bytes += outbox_[j].msg.size();
      ++j;
    }
    w.varint(j - i);
    for (std::size_t k = i; k < j; ++k) {
      // A message is its type byte followed by its body; the length covers the body.
      const auto& m = outbox_[k].msg;
      w.u8(m[0]);
      w.varint(m.size() - 1);
      w.raw(m.data() + 1, m.size() - 1);
    }
    ++stats_.frames_sent;
    stats_.bytes_sent += frame.size();
    if (to.is_null()) t_.broadcast(frame);
    else t_.send(to, frame);
    i = j;
  }
  outbox_.clear();
}

void Replicator::reject(const Error& e) {
  ++stats_.rejected_frames;
  if (error_cb_) error_cb_(e);
}

void Replicator::on_frame(std::span<const std::uint8_t> frame, std::int64_t now_ns) {
  now_ = std::max(now_, now_ns);
  wire::Reader r(frame, "replication frame");
  std::uint8_t m0 = r.u8("magic"), m1 = r.u8("magic"), version = r.u8("version");
  if (!r.ok()) return reject(r.error());
  if (m0 != kMagic0 || m1 != kMagic1) {
    r.fail(ErrorCode::kMalformed, "magic", "not a Quiver replication frame");
    return reject(r.error());
  }
  if (version != kVersion) {
    r.fail(ErrorCode::kUnsupportedVersion, "version",
           "protocol version " + std::to_string(version) + " (this build speaks " + std::to_string(kVersion) + ")");
    return reject(r.error());
  }
  PeerId from = crdt::decode_replica(r, "sender");
  std::uint8_t unicast = r.u8("destination flag");
  PeerId to;
  if (unicast == 1) to = crdt::decode_replica(r, "destination");
  else if (unicast != 0 && r.ok()) r.fail(ErrorCode::kMalformed, "destination flag", "must be 0 or 1");
  if (!r.ok()) return reject(r.error());
  if (from == self_ || from.is_null()) return;
  if (unicast == 1 && !(to == self_)) return;
  ++stats_.frames_received;
  stats_.bytes_received += frame.size();
  std::uint64_t n = r.count("message count", kMaxChunks, 2);
  if (!r.ok()) return reject(r.error());
  heard_from(from);
  for (std::uint64_t i = 0; i < n; ++i) {
    std::uint8_t type = r.u8("message type");
    auto body = r.bytes("message body", kMaxMessageBytes);
    if (!r.ok()) return reject(r.error());
    switch (type) {
      case kSummary: handle_summary(from, body); break;
      case kDelta: handle_delta(from, body); break;
      case kPull: handle_pull(from, body); break;
      case kState: handle_state(from, body); break;
      case kBye: mark_left(peers_[from]); break;
      default:
        reject(make_error(ErrorCode::kMalformed, "replication frame from " + from.to_string() +
                                                     ": unknown message type " + std::to_string(type)));
    }
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

void Replicator::send_summary() {
  std::vector<std::uint8_t> msg;
  wire::Writer w(msg);
  w.u8(kSummary);
  w.string(opt_.name);
  w.varint(opt_.observer ? 1 : 0);
  crdt::encode_context(applied_, w);
  queue(PeerId{}, std::move(msg));
}

void Replicator::handle_summary(const PeerId& from, std::span<const std::uint8_t> body) {
  wire::Reader r(body, "summary");
  std::string name(r.string("agent name", 1024));
  std::uint64_t flags = r.varint("flags");
  crdt::CausalContext their;
  crdt::decode_context(r, their);
  if (!r.ok()) return reject(r.error());
  Peer& p = peers_[from];
  bool first = p.info.name.empty() && p.applied.empty();
  p.info.name = std::move(name);
  p.info.observer = flags & 1;
  p.applied = std::move(their);
  if (first) send_summary();  // let a newcomer learn about us without waiting a heartbeat
  if (pulling_ && pull_target_ == from && !behind(p)) pulling_ = false;  // nothing more there
  if (!pulling_ && behind(p)) pull_from(from);
}

void Replicator::handle_delta(const PeerId& from, std::span<const std::uint8_t> body) {
  wire::Reader r(body, "delta message");
  PeerId origin = crdt::decode_replica(r, "origin");
  std::uint64_t lo = r.varint("first sequence number");
  std::uint64_t len = r.varint("sequence count");
  auto bytes = r.bytes("delta", kMaxMessageBytes);
  if (r.ok() && (lo == 0 || lo + len < lo)) r.fail(ErrorCode::kMalformed, "sequence numbers", "invalid range");
  if (!r.ok()) return reject(r.error());
  const std::uint64_t hi = lo + len;
  if (origin == self_) return;
  crdt::CausalContext range;
  range.add_range(origin, lo, hi);
  if (applied_.includes(range)) {
    ++stats_.deltas_duplicate;
    return;
  }
  Status s = graph::decode(bytes, scratch_);
  if (!s.ok()) {
    return reject(make_error(s.error().code, "delta " + origin.to_string() + "#" + std::to_string(lo) +
                                                 " relayed by " + from.to_string() + ": " + s.error().message));
  }
  if (!(scratch_.origin == origin) || scratch_.kind != graph::GraphDelta::Kind::kDelta)
    return reject(make_error(ErrorCode::kMalformed, "delta " + origin.to_string() + "#" + std::to_string(lo) +
                                                        ": the payload's origin or kind does not match"));
  g_.merge(scratch_);
  applied_.add_range(origin, lo, hi);
  ++stats_.deltas_applied;
  remember(origin, lo, hi, std::make_shared<const std::vector<std::uint8_t>>(bytes.begin(), bytes.end()));
  if (applied_.contiguous(origin) + 1 < lo && !gap_pending_) {
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
  std::vector<std::uint8_t> msg;
  wire::Writer w(msg);
  w.u8(kPull);
  w.varint(pull_request_);
  crdt::encode_context(applied_, w);
  crdt::encode_context(g_.context(), w);
  queue(target, std::move(msg));
}

void Replicator::handle_pull(const PeerId& from, std::span<const std::uint8_t> body) {
  wire::Reader r(body, "pull");
  std::uint64_t request = r.varint("request id");
  crdt::CausalContext their_applied, their_ctx;
  crdt::decode_context(r, their_applied);
  crdt::decode_context(r, their_ctx);
  if (!r.ok()) return reject(r.error());
  crdt::CausalContext missing = applied_.minus(their_applied);
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
      cur = e.hi + 1;
    }
  });
  if (covered) {
    ++stats_.pulls_answered_with_deltas;
    for (const Buffered* e : entries) {
      queue(from, delta_message(e->origin, e->lo, e->hi, *e->bytes));
      ++stats_.deltas_relayed;
    }
    return;
  }
  ++stats_.pulls_answered_with_state;
  std::vector<std::uint8_t> state = graph::encode(g_.state_diff(their_ctx));
  const std::size_t chunk = std::max<std::size_t>(opt_.chunk_bytes, 1024);
  const std::uint64_t count = std::max<std::uint64_t>(1, (state.size() + chunk - 1) / chunk);
  for (std::uint64_t i = 0; i < count; ++i) {
    std::vector<std::uint8_t> msg;
    wire::Writer w(msg);
    w.u8(kState);
    w.varint(request);
    w.varint(i);
    w.varint(count);
    if (i == 0) crdt::encode_context(applied_, w);
    std::size_t begin = i * chunk, end = std::min(state.size(), begin + chunk);
    w.bytes(std::span<const std::uint8_t>(state.data() + begin, end - begin));
    queue(from, std::move(msg));
  }
}

void Replicator::handle_state(const PeerId& from, std::span<const std::uint8_t> body) {
  wire::Reader r(body, "state chunk");
  std::uint64_t request = r.varint("request id");
  std::uint64_t index = r.varint("chunk index");
  std::uint64_t count = r.bounded("chunk count", kMaxChunks);
  if (r.ok() && (count == 0 || index >= count)) r.fail(ErrorCode::kMalformed, "chunk index", "out of range");
  crdt::CausalContext their_applied;
  if (index == 0) crdt::decode_context(r, their_applied);
  auto bytes = r.bytes("chunk", kMaxMessageBytes);
  if (!r.ok()) return reject(r.error());
  Reassembly& ra = reassembly_[from];
  if (ra.request != request || ra.count != count) {
    ra = Reassembly{};
    ra.request = request;
    ra.count = count;
    ra.started_ns = now_;
    ra.chunks.resize(count);
  }
  if (!ra.chunks[index].empty() || (bytes.empty() && count > 1)) return;  // duplicate
  ra.chunks[index].assign(bytes.begin(), bytes.end());
  ++ra.received;
  ra.bytes += bytes.size();
  if (index == 0) ra.applied = std::move(their_applied);
  if (ra.received < count) return;
  std::vector<std::uint8_t> all;
  all.reserve(ra.bytes);
  for (const auto& c : ra.chunks) all.insert(all.end(), c.begin(), c.end());
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

// ------------------------------------------------------------------ buffer

void Replicator::remember(const PeerId& origin, std::uint64_t lo, std::uint64_t hi,
                          std::shared_ptr<const std::vector<std::uint8_t>> bytes) {
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
  // Drop what every live peer already holds: acknowledged by their summaries.
  std::vector<const Peer*> live;
  for (const auto& [id, p] : peers_)
    if (p.info.alive) live.push_back(&p);
  if (live.empty()) return;
  for (auto it = buffer_.begin(); it != buffer_.end();) {
    crdt::CausalContext range;
    range.add_range(it->origin, it->lo, it->hi);
    bool acked = true;
    for (const Peer* p : live) acked = acked && p->applied.includes(range);
    if (!acked) {
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

void Replicator::leave() {
  flush();
  queue(PeerId{}, std::vector<std::uint8_t>{kBye});
  send_queued();
}

void Replicator::tick(std::int64_t now_ns) {
  now_ = std::max(now_, now_ns);
  if (opt_.coalesce) flush();
  if (pulling_ && now_ - pull_sent_ns_ > opt_.pull_timeout_ns) {
    pulling_ = false;
    last_failed_target_ = pull_target_;
    ++stats_.pulls_timed_out;
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
      auto it = peers_.find(gap_peer_);
      if (it != peers_.end() && it->second.info.alive) pull_from(gap_peer_);
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
