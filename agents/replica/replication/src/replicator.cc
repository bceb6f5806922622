// Replicator: construction, local deltas coalesced and published under this replica's sequence
// numbers, incoming samples validated and dispatched, and the memory its protocol state takes.

#include "quiver/agents/replica/replication/replicator.h"

#include "quiver/base/stage_marks.h"

#include <algorithm>

#include "quiver/graph/codec.h"
#include "replicator_detail.h"

namespace quiver::agents::inline replica {
using internal::digest_of;

namespace {

// Rough encoded size of a local delta, to keep a coalesced interval within a delta's limit.
std::size_t approx_bytes(const graph::GraphDelta& d) {
  std::size_t n = 64 + 40 * (d.nodes.size() + d.edges.size() + d.attrs.size() + d.removed.size() + d.added.size()) +
                  96 * (d.claims.size() + d.samples.size());
  for (const auto& e : d.values) n += 16 + e.value.payload_bytes();
  for (const auto& node : d.nodes) n += node.name.size();
  return n;
}

}  // namespace

Replicator::Replicator(graph::Graph& g, Transport& t, ReplicatorOptions options)
    : g_(g), t_(t), opt_(std::move(options)), self_(g.replica()) {
  opt_.max_peers = std::min(opt_.max_peers, PeerTable::kMaxPeers);
  g_.set_delta_sink([this](const graph::GraphDelta& d) { on_local_delta(d); });
  g_.set_origin_namer([this](const PeerId& id, std::string& name) { write_name(id, name); });
}

Replicator::~Replicator() {
  g_.set_delta_sink(nullptr);
  g_.set_origin_namer(nullptr);
}

std::string Replicator::name_of(const PeerId& id) const {
  std::string name;
  write_name(id, name);
  return name;
}

void Replicator::write_name(const PeerId& id, std::string& out) const {
  if (id == self_ && !opt_.name.empty()) return (void)out.assign(opt_.name);
  if (id == self_) return id.write_to(out);
  if (auto p = peers_.find(id); p != peers_.end() && !seen(p->second).name.empty())
    return (void)out.assign(seen(p->second).name);
  if (auto n = names_.find(id.agent); n != names_.end()) return (void)out.assign(n->second);
  // A world seed's changes (graph::world_seed(): incarnation 0, never an agent's) have no agent.
  if (id.incarnation == 0) return (void)out.assign("world seed " + id.to_string().substr(0, 16));
  id.write_to(out);
}

std::string Replicator::who(const PeerId& id) const {
  std::string name = name_of(id);
  const std::string hex = id.to_string();
  return name == hex ? hex : "'" + name + "' (" + hex + ")";
}

std::string Replicator::delta_of(const PeerId& origin, std::uint64_t lo, std::uint64_t hi) const {
  return "(" + who(origin) + ", " + std::to_string(lo) + (hi == lo ? "" : ".." + std::to_string(hi)) + ")";
}

// ------------------------------------------------------------------ local deltas

void Replicator::on_local_delta(const graph::GraphDelta& d) {
  ++state_version_;
  if (opt_.coalesce) {
    const std::size_t bytes = approx_bytes(d);
    // An interval covers at most max_interval commits and stays within a delta's size limit. A
    // commit that claims a rule (docs/grammar.md) travels alone: a joined interval carries no
    // claim (GraphDelta::append()), and its receivers could not verify it.
    if (pending_lo_ != 0 && (seq_ + 1 - pending_lo_ >= opt_.limits.max_interval ||
                             pending_bytes_ + bytes > graph::limits::kMaxDeltaBytes || !d.rule.empty() ||
                             !pending_.rule.empty()))
      flush();
    ++seq_;
    applied_.add(crdt::Dot{self_, seq_});
    if (journal_ != nullptr) {
      std::vector<std::uint8_t> bytes;
      graph::encode(d, bytes, seq_, seq_);
      journal_->local(seq_, bytes);
    }
    if (pending_lo_ == 0) {
      pending_ = d;
      pending_lo_ = seq_;
      pending_bytes_ = bytes;
    } else {
      pending_.append(d);
      pending_bytes_ += bytes;
    }
    return;
  }
  ++seq_;
  applied_.add(crdt::Dot{self_, seq_});
  auto bytes = fresh_bytes();
  graph::encode(d, *bytes, seq_, seq_);
  stage_marks::mark(stage_marks::Stage::kEncoded);
  if (journal_ != nullptr) journal_->local(seq_, *bytes);
  publish(std::move(bytes), seq_, seq_);
}

void Replicator::flush() {
  if (pending_lo_ == 0) return;
  std::uint64_t lo = pending_lo_;
  auto bytes = fresh_bytes();
  graph::encode(pending_, *bytes, lo, seq_);
  stage_marks::mark(stage_marks::Stage::kEncoded);
  publish(std::move(bytes), lo, seq_);
  pending_.clear();
  pending_lo_ = 0;
  pending_bytes_ = 0;
}

void Replicator::publish(std::shared_ptr<std::vector<std::uint8_t>> bytes, std::uint64_t lo, std::uint64_t hi) {
  Bytes shared = std::move(bytes);
  Bytes signature;
  if (admission_ != nullptr)
    if (auto sig = admission_->sign(*shared); !sig.empty())
      signature = std::make_shared<const std::vector<std::uint8_t>>(std::move(sig));
  stage_marks::mark(stage_marks::Stage::kSigned);
  applied_.add_range(self_, lo, hi);
  ++state_version_;
  applied_changed_ns_ = now_;
  remember(self_, lo, hi, digest_of(*shared), shared, signature, true);
  ++stats_.deltas_published;
  stats_.bytes_published += shared->size();
  const bool signed_delta = signature != nullptr;
  queue(PeerId{}, DeltaMsg{self_, lo, hi, std::move(shared), std::move(signature)});
  send_queued();
  if (signed_delta) admission_->prepare();  // the next signature's costly part, now it is sent
}

Result<bool> Replicator::seed(const graph::GraphDelta& d) {
  if (d.seq_lo == 0 || d.seq_hi < d.seq_lo || d.origin.is_null() || d.origin == self_)
    return make_error(ErrorCode::kInvalidArgument, "seed(): the delta must name its origin and sequence interval");
  if (applied_.includes(d.origin, d.seq_lo, d.seq_hi)) return false;
  auto bytes = std::make_shared<const std::vector<std::uint8_t>>(graph::encode(d));
  g_.merge(d);
  ++state_version_;
  applied_.add_range(d.origin, d.seq_lo, d.seq_hi);
  if (journal_ != nullptr) journal_->remote(d.origin, d.seq_lo, d.seq_hi, *bytes);
  remember(d.origin, d.seq_lo, d.seq_hi, digest_of(*bytes), bytes, nullptr);
  DeltaMsg m{d.origin, d.seq_lo, d.seq_hi, std::move(bytes), nullptr};
  queue(PeerId{}, m);
  send_queued();
  joined(&m);
  return true;
}

// ------------------------------------------------------------------ samples

void Replicator::queue(const PeerId& to, Message msg) { outbox_.push_back(Sample{self_, to, std::move(msg)}); }

// One sample per message, in the order they were queued: what DDS ships is what the simulator
// carries, and nothing here batches what a transport would have to split again.
void Replicator::send_queued() {
  for (const Sample& s : outbox_) {
    ++stats_.samples_sent;
    t_.send(s);
  }
  outbox_.clear();
}

void Replicator::reject(const Error& e) {
  ++stats_.rejected;
  if (error_cb_) error_cb_(e);
}

void Replicator::equivocation(const std::string& what) {
  ++stats_.equivocations;
  if (error_cb_) error_cb_(make_error(ErrorCode::kEquivocation, what));
}

void Replicator::on_undecodable(const Error& e) { reject(e); }

void Replicator::on_sample(const Sample& s, std::int64_t now_ns) {
  now_ = std::max(now_, now_ns);
  if (s.from == self_ || s.from.is_null()) return;
  if (!s.to.is_null() && !(s.to == self_)) return;
  if (Status st = validate(s, opt_.limits, [this](const PeerId& id) { return who(id); }); !st.ok())
    return reject(st.error());
  ++stats_.samples_received;
  if (heard_from(s.from) == nullptr) return;
  addressed_ = !s.to.is_null();
  sender_ = s.sender;
  std::visit([&](const auto& msg) { handle(s.from, msg); }, s.message);
  sender_ = {};
  if (announce_soon_) {
    announce_soon_ = false;
    if (!opt_.gossip) send_summary();
  }
  // Gossip: the origins of claims this sample brought are told at once that we hold them.
  for (const PeerId& o : ack_to_) send_beat(Beat::kAck, o);
  ack_to_.clear();
  send_queued();
  // A claim's acknowledgements come from every peer at once: their reports go here, where no
  // detail is in use, not at the next sweep (peer_table.h).
  if (opt_.gossip && peers_.details().size() > kMaxDetails + kMaxDetails / 4) trim_details();
}

std::size_t Replicator::protocol_bytes() const {
  // Estimates: a std::map node costs its value plus about 48 bytes; a string its capacity
  // beyond the small-string buffer.
  constexpr std::size_t kNode = 48;
  std::size_t n = sizeof(*this) + peers_.memory_bytes();
  for (const auto& [agent, name] : names_) n += kNode + sizeof(agent) + sizeof(name) + (name.capacity() > 15 ? name.capacity() : 0);
  n += rumors_.capacity() * sizeof(Spreading) + mismatched_.size() * (kNode + 24);
  n += applied_.memory_bytes();
  // Teams (replicator_behind.cc): who waits, who is behind gateway peers, who is behind us.
  n += askers_.capacity() * sizeof(Asker) + remote_.size() * (kNode + sizeof(PeerId) + sizeof(Behind));
  n += behind_out_.capacity() * sizeof(Member);
  return n;
}

PeerInfo Replicator::info_of(const Peer& p) const {
  const PeerDetail& pd = seen(p);
  PeerInfo info;
  info.id = p.id;
  if (pd.name.empty()) {
    if (auto n = names_.find(p.id.agent); n != names_.end()) info.name = n->second;
  } else {
    info.name = pd.name;
  }
  info.observer = p.observer;
  info.gateway = pd.gateway;
  info.alive = p.alive;
  info.last_heard_ns = pd.heard_ns;
  return info;
}

}  // namespace quiver::agents
