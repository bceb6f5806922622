#include "quiver/agents/replica/replication/replicator.h"

#include <algorithm>

#include "quiver/graph/codec.h"

namespace quiver::agents::inline replica {
namespace {

std::uint64_t digest_of(const std::vector<std::uint8_t>& bytes) {
  Hasher h(0xde17a);
  h.bytes(bytes.data(), bytes.size());
  return h.h64();
}

std::string interval(const PeerId& origin, std::uint64_t lo, std::uint64_t hi) {
  return "(" + origin.to_string() + ", " + std::to_string(lo) + (hi == lo ? "" : ".." + std::to_string(hi)) + ")";
}

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
  g_.set_delta_sink([this](const graph::GraphDelta& d) { on_local_delta(d); });
  g_.set_origin_namer([this](const PeerId& id) { return name_of(id); });
}

Replicator::~Replicator() {
  g_.set_delta_sink(nullptr);
  g_.set_origin_namer(nullptr);
}

std::string Replicator::name_of(const PeerId& id) const {
  if (id == self_) return opt_.name.empty() ? id.to_string() : opt_.name;
  if (auto p = peers_.find(id); p != peers_.end() && !p->second.info.name.empty()) return p->second.info.name;
  if (auto n = names_.find(id.agent); n != names_.end()) return n->second;
  return id.to_string();
}

// ------------------------------------------------------------------ local deltas

void Replicator::on_local_delta(const graph::GraphDelta& d) {
  ++state_version_;
  if (opt_.coalesce) {
    const std::size_t bytes = approx_bytes(d);
    // An interval covers at most max_interval commits and stays within a delta's size limit.
    if (pending_lo_ != 0 && (seq_ + 1 - pending_lo_ >= opt_.limits.max_interval ||
                             pending_bytes_ + bytes > graph::limits::kMaxDeltaBytes))
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
  std::vector<std::uint8_t> bytes;
  graph::encode(d, bytes, seq_, seq_);
  if (journal_ != nullptr) journal_->local(seq_, bytes);
  publish(std::move(bytes), seq_, seq_);
}

void Replicator::flush() {
  if (pending_lo_ == 0) return;
  std::uint64_t lo = pending_lo_;
  std::vector<std::uint8_t> bytes;
  graph::encode(pending_, bytes, lo, seq_);
  publish(std::move(bytes), lo, seq_);
  pending_.clear();
  pending_lo_ = 0;
  pending_bytes_ = 0;
}

void Replicator::publish(std::vector<std::uint8_t> bytes, std::uint64_t lo, std::uint64_t hi) {
  auto shared = std::make_shared<const std::vector<std::uint8_t>>(std::move(bytes));
  Bytes signature;
  if (admission_ != nullptr)
    if (auto sig = admission_->sign(*shared); !sig.empty())
      signature = std::make_shared<const std::vector<std::uint8_t>>(std::move(sig));
  applied_.add_range(self_, lo, hi);
  record(self_, lo, hi, digest_of(*shared));
  remember(self_, lo, hi, shared, signature);
  ++stats_.deltas_published;
  queue(PeerId{}, DeltaMsg{self_, lo, hi, std::move(shared), std::move(signature)});
  send_queued();
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
  record(d.origin, d.seq_lo, d.seq_hi, digest_of(*bytes));
  remember(d.origin, d.seq_lo, d.seq_hi, bytes, nullptr);
  queue(PeerId{}, DeltaMsg{d.origin, d.seq_lo, d.seq_hi, std::move(bytes), nullptr});
  send_queued();
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
  if (Status st = validate(s, opt_.limits); !st.ok()) return reject(st.error());
  ++stats_.samples_received;
  if (heard_from(s.from) == nullptr) return;
  std::visit([&](const auto& msg) { handle(s.from, msg); }, s.message);
  if (announce_soon_) {
    announce_soon_ = false;
    send_summary();
  }
  send_queued();
}

// ------------------------------------------------------------------ membership

Replicator::Peer* Replicator::heard_from(const PeerId& from) {
  auto it = peers_.find(from);
  if (it == peers_.end()) {
    if (peers_.size() >= opt_.max_peers) {
      // Make room from peers that are gone; a table full of live ones refuses the newcomer.
      for (auto g = peers_.begin(); g != peers_.end() && peers_.size() >= opt_.max_peers;) {
        if (!g->second.info.alive) {
          peer_ranges_ -= g->second.applied.range_count();
          g = peers_.erase(g);
        } else {
          ++g;
        }
      }
      if (peers_.size() >= opt_.max_peers) {
        ++stats_.peers_refused;
        reject(make_error(ErrorCode::kTooLarge, "from " + from.to_string() + ": the peer table is full (" +
                                                    std::to_string(opt_.max_peers) + " peers); ignored"));
        return nullptr;
      }
    }
    it = peers_.try_emplace(from).first;
    it->second.info.id = from;
  }
  Peer& p = it->second;
  if (p.said_bye) return nullptr;  // a late message of an incarnation that left cleanly
  p.info.last_heard_ns = now_;
  if (!p.info.alive) {
    p.info.alive = true;
    // A new incarnation of an agent means the old one is gone.
    for (auto& [id, other] : peers_)
      if (other.info.alive && id.agent == from.agent && !(id == from) && id.incarnation < from.incarnation)
        mark_left(other);
    if (membership_cb_ && p.announced) membership_cb_(Membership::kJoined, p.info);
  }
  return &p;
}

void Replicator::mark_left(Peer& p) {
  if (!p.info.alive) return;
  p.info.alive = false;
  if (state_.active && pull_target_ == p.info.id) state_ = Reassembly{};
  if (pulling_ && pull_target_ == p.info.id) pulling_ = false;
  if (membership_cb_ && p.announced) membership_cb_(Membership::kLeft, p.info);
}

void Replicator::on_peer_lost(const PeerId& peer, bool gone) {
  auto it = peers_.find(peer);
  if (it == peers_.end()) return;
  mark_left(it->second);
  if (gone) it->second.said_bye = true;
}

std::vector<PeerInfo> Replicator::peers() const {
  std::vector<PeerInfo> out;
  for (const auto& [id, p] : peers_) {
    out.push_back(p.info);
    out.back().suspect = p.suspect_until > now_;
  }
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

bool Replicator::peers_hold_all() const {
  for (const auto& [id, p] : peers_)
    if (counts(p) && !p.info.observer && !p.applied.includes(applied_)) return false;
  return true;
}

// A live peer whose summaries are believed (not suspected of claiming what it never delivers).
bool Replicator::counts(const Peer& p) const { return p.info.alive && p.suspect_until <= now_; }

bool Replicator::synced() const {
  bool any = false;
  for (const auto& [id, p] : peers_) {
    if (!counts(p)) continue;
    any = true;
    if (behind(p)) return false;
  }
  return any && !state_.active;
}

// ------------------------------------------------------------------ messages

void Replicator::send_summary(bool with_digest) {
  SummaryMsg m{opt_.name, opt_.observer, to_ranges(applied_)};
  {
    // Kept (without the digest) for a keeper to send again while the owner thread is busy.
    auto copy = std::make_shared<const Sample>(Sample{self_, PeerId{}, m});
    std::lock_guard<std::mutex> lock(heartbeat_mu_);
    heartbeat_ = std::move(copy);
  }
  // Coalesced local changes not yet published would make the digest differ for a while.
  if (with_digest && pending_lo_ == 0) m.digest = state_digest();
  queue(PeerId{}, std::move(m));
}

std::shared_ptr<const Sample> Replicator::last_heartbeat() const {
  std::lock_guard<std::mutex> lock(heartbeat_mu_);
  return heartbeat_;
}

std::uint64_t Replicator::state_digest() {
  if (digest_version_ != state_version_) {
    digest_ = g_.digest().lo;
    if (digest_ == 0) digest_ = 1;
    digest_version_ = state_version_;
  }
  return digest_;
}

// The same (origin, seq) set should mean the same state: a join is deterministic. Another digest
// means a payload was forged under numbers both hold (an equivocation one of us never saw, or a
// forged interval covering real ones). Twice in a row (a commit may be racing the summary), this
// replica asks that peer for its whole state; the peer does the same, and the joins converge.
void Replicator::check_digest(const PeerId& from, Peer& p, std::uint64_t digest) {
  if (digest == 0 || p.state_refused || pulling_ || state_.active || pending_lo_ != 0 || !(p.applied == applied_)) return;
  if (digest == state_digest()) {
    p.digest_mismatches = 0;
    return;
  }
  if (++p.digest_mismatches < 2) return;
  p.digest_mismatches = 0;
  ++stats_.divergences;
  equivocation("replica " + from.to_string() + " holds the same deltas as this one but another state: pulling its whole state");
  pull_from(from, true);
}

void Replicator::handle(const PeerId& from, const SummaryMsg& m) {
  Peer& p = peers_[from];
  crdt::CausalContext applied = to_context(m.applied);
  const std::size_t total = peer_ranges_ - p.applied.range_count() + applied.range_count();
  if (total > opt_.max_peer_ranges)
    return reject(make_error(ErrorCode::kTooLarge, "summary from " + from.to_string() + ": " +
                                                       std::to_string(applied.range_count()) +
                                                       " ranges would exceed the peer table's limit"));
  peer_ranges_ = total;
  const bool first = !p.announced;
  p.info.name = m.name;
  p.info.observer = m.observer;
  // Remembered past the peer's departure (deltas it made keep arriving through others), but only
  // a name that hashes to the id it came with: nobody can name another agent's changes.
  if (!m.name.empty() && fnv1a64(m.name) == from.agent && names_.size() < 4 * opt_.max_peers)
    names_.emplace(from.agent, m.name);
  p.applied = std::move(applied);
  if (first) {
    p.announced = true;
    if (membership_cb_ && p.info.alive) membership_cb_(Membership::kJoined, p.info);
    send_summary();  // let a newcomer learn about us without waiting a heartbeat
  }
  if (!behind(p)) p.pull_failures = 0;  // it holds nothing we lack: no claim to doubt
  if (pulling_ && pull_target_ == from && !behind(p)) {  // caught up with it: the pull is done
    pulling_ = false;
    pull_timeouts_in_a_row_ = 0;
  }
  // A sampling observer pulls on its own clock (tick()), not at every summary.
  if (!pulling_ && opt_.sample_ns == 0 && counts(p) && behind(p)) pull_from(from);
  if (counts(p)) check_digest(from, p, m.digest);
}

void Replicator::record(const PeerId& origin, std::uint64_t lo, std::uint64_t hi, std::uint64_t digest) {
  if (opt_.equivocation_window == 0) return;
  if (seen_order_.size() < opt_.equivocation_window) {
    seen_order_.emplace_back(origin, lo);
  } else {  // the ring is full: forget the oldest record
    auto& [o, l] = seen_order_[seen_next_];
    if (auto it = seen_.find(o); it != seen_.end()) {
      it->second.erase(l);
      if (it->second.empty()) seen_.erase(it);
    }
    seen_order_[seen_next_] = {origin, lo};
    seen_next_ = (seen_next_ + 1) % seen_order_.size();
  }
  seen_[origin][lo] = Seen{hi, digest, {}};
}

const Replicator::Seen* Replicator::recorded(const PeerId& origin, std::uint64_t lo) const {
  auto it = seen_.find(origin);
  if (it == seen_.end()) return nullptr;
  auto s = it->second.find(lo);
  return s == it->second.end() ? nullptr : &s->second;
}

Status Replicator::decode_delta(const PeerId& from, const DeltaMsg& m) {
  const std::string what = "delta " + interval(m.origin, m.lo, m.hi) + " relayed by " + from.to_string();
  Status s = graph::decode(*m.payload, scratch_);
  if (!s.ok()) return make_error(s.error().code, what + ": " + s.error().message);
  if (!(scratch_.origin == m.origin) || scratch_.kind != graph::GraphDelta::Kind::kDelta)
    return make_error(ErrorCode::kMalformed, what + ": the payload's origin or kind does not match");
  if (scratch_.seq_lo != m.lo || scratch_.seq_hi != m.hi)
    return make_error(ErrorCode::kMalformed, what + ": the payload names the interval [" +
                                                 std::to_string(scratch_.seq_lo) + ", " +
                                                 std::to_string(scratch_.seq_hi) + "], not the one claimed");
  return {};
}

void Replicator::apply_delta(const PeerId& from, const DeltaMsg& m, std::uint64_t digest) {
  g_.merge(scratch_);
  ++state_version_;
  applied_.add_range(m.origin, m.lo, m.hi);
  if (journal_ != nullptr) journal_->remote(m.origin, m.lo, m.hi, *m.payload);
  record(m.origin, m.lo, m.hi, digest);
  ++stats_.deltas_applied;
  remember(m.origin, m.lo, m.hi, m.payload, m.signature);
  if (auto it = peers_.find(from); it != peers_.end() && pulling_ && pull_target_ == from) it->second.pull_failures = 0;
  if (applied_.contiguous(m.origin) + 1 < m.lo && !gap_pending_) {
    gap_pending_ = true;
    gap_since_ns_ = now_;
    gap_peer_ = from;
  }
}

void Replicator::handle(const PeerId& from, const DeltaMsg& m) {
  if (m.origin == self_) return handle_own(from, m);
  const std::uint64_t digest = digest_of(*m.payload);
  if (applied_.includes(m.origin, m.lo, m.hi)) {
    const Seen* seen = recorded(m.origin, m.lo);
    if (seen == nullptr || seen->knows(m.hi, digest)) {
      ++stats_.deltas_duplicate;
      return;
    }
    return equivocate(from, m, digest, "differs from the one already applied under that interval");
  }
  if (applied_.intersects(m.origin, m.lo, m.hi))
    return equivocate(from, m, digest, "overlaps intervals already applied");
  if (Status s = decode_delta(from, m); !s.ok()) return reject(s.error());
  if (!admitted(from, m, digest)) return;
  apply_delta(from, m, digest);
}

// The Admission's verdict on the decoded delta in scratch_. A refused delta is never applied,
// but its interval counts as received and it is relayed like any other: every replica sees it
// and refuses it alike (the verdict depends on the delta and the policy only), so the replicas
// stay equal and nobody pulls it for ever.
bool Replicator::admitted(const PeerId& from, const DeltaMsg& m, std::uint64_t digest) {
  Status s = admission_verdict(from, m);
  if (s.ok()) return true;
  applied_.add_range(m.origin, m.lo, m.hi);
  record(m.origin, m.lo, m.hi, digest);
  remember(m.origin, m.lo, m.hi, m.payload, m.signature);
  queue(PeerId{}, DeltaMsg{m.origin, m.lo, m.hi, m.payload, m.signature});
  reject(s.error());
  return false;
}

// The Admission's verdict on the decoded delta in scratch_ (ok without one); a refusal is counted
// and names the delta and its relay.
Status Replicator::admission_verdict(const PeerId& from, const DeltaMsg& m) {
  if (admission_ == nullptr) return {};
  const std::span<const std::uint8_t> sig =
      m.signature ? std::span<const std::uint8_t>(*m.signature) : std::span<const std::uint8_t>();
  Status s = admission_->admit_delta(scratch_, *m.payload, sig);
  if (s.ok()) return s;
  ++stats_.deltas_refused;
  return make_error(ErrorCode::kPermissionDenied, "delta " + interval(m.origin, m.lo, m.hi) + " relayed by " +
                                                      from.to_string() + " refused: " + s.error().message);
}

// Two payloads under one (origin, seq): one of them is forged (or a replica is broken). Which,
// nobody can tell without authenticated identities; refusing the second would leave replicas that
// received them in different orders apart for good. So both are joined (a join does not care about
// order), and the equivocation is reported, with both senders' evidence.
//
// Every version must reach every replica, whichever it got first: a replica that learns of a
// second version sends it to all, with the version it had (from its relay buffer), once per
// version; every replica does the same, so the versions flood and every replica joins all of them.
void Replicator::equivocate(const PeerId& from, const DeltaMsg& m, std::uint64_t digest, const std::string& what) {
  equivocation("delta " + interval(m.origin, m.lo, m.hi) + " relayed by " + from.to_string() + " " + what +
               ": both are joined");
  if (Status s = decode_delta(from, m); !s.ok()) return reject(s.error());
  if (Status a = admission_verdict(from, m); !a.ok()) return reject(a.error());
  g_.merge(scratch_);
  ++state_version_;
  applied_.add_range(m.origin, m.lo, m.hi);
  if (journal_ != nullptr) journal_->remote(m.origin, m.lo, m.hi, *m.payload);
  // Remembered by its interval's end and digest, so that its echoes are duplicates: relayed
  // versions that were not would bounce between the replicas for ever.
  Seen* seen = recorded(m.origin, m.lo);
  bool first_other = false;
  if (seen == nullptr) {
    record(m.origin, m.lo, m.hi, digest);
  } else if (seen->others.size() < opt_.max_versions) {
    first_other = seen->others.empty();
    seen->others.push_back(Version{m.hi, digest});
  } else {
    ++stats_.versions_not_relayed;
    return;
  }
  queue(PeerId{}, DeltaMsg{m.origin, m.lo, m.hi, m.payload, m.signature});
  if (first_other) {
    auto idx = buffer_index_.find(m.origin);
    if (idx != buffer_index_.end())
      if (auto it = idx->second.find(m.lo); it != idx->second.end())
        queue(PeerId{}, DeltaMsg{m.origin, it->second->lo, it->second->hi, it->second->bytes, it->second->signature});
  }
}

// A delta that claims this replica as its origin. An echo of what we published is a duplicate;
// one that differs from it, or one naming numbers we never published, was forged under our name.
void Replicator::handle_own(const PeerId& from, const DeltaMsg& m) {
  const std::uint64_t digest = digest_of(*m.payload);
  if (applied_.includes(self_, m.lo, m.hi)) {
    const Seen* seen = recorded(self_, m.lo);
    if (seen == nullptr || seen->knows(m.hi, digest)) {
      ++stats_.deltas_duplicate;
      return;
    }
    return equivocate(from, m, digest, "claims to be ours but differs from what we published");
  }
  // Numbers this replica never published: someone publishes under our name. Peers may already
  // hold it, so this replica takes it too (every replica must hold the same), and our next
  // deltas take sequence numbers (and dots, by the Lamport rule) beyond it. Checked first: a
  // payload that does not decode moves nothing.
  if (Status s = decode_delta(from, m); !s.ok()) return reject(s.error());
  const bool overlaps = applied_.intersects(self_, m.lo, m.hi);
  skip_own_numbers_to(m.hi);
  if (overlaps) return equivocate(from, m, digest, "claims to be ours but differs from what we published");
  if (!admitted(from, m, digest)) return;
  equivocation("delta " + interval(m.origin, m.lo, m.hi) + " relayed by " + from.to_string() +
               " was published under this replica's name, which never published it; later deltas take sequence "
               "numbers beyond it");
  apply_delta(from, m, digest);
}

// Our next sequence number goes beyond `hi` (someone used numbers of ours): coalesced local
// changes are published first under the numbers they already have, and the numbers up to `hi`
// nobody published here are marked used, so that [1, seq_] stays in applied_.
void Replicator::skip_own_numbers_to(std::uint64_t hi) {
  if (hi <= seq_) return;
  flush();
  applied_.add_range(self_, seq_ + 1, hi);
  if (journal_ != nullptr) journal_->skipped(seq_ + 1, hi);
  seq_ = hi;
}

void Replicator::pull_from(const PeerId& target, bool whole_state) {
  pulling_ = true;
  pull_target_ = target;
  pull_sent_ns_ = now_;
  ++pull_request_;
  ++stats_.pulls_sent;
  state_ = Reassembly{};
  queue(target, PullMsg{pull_request_, to_ranges(applied_), to_ranges(g_.context()), whole_state,
                        /*as_state=*/opt_.sample_ns > 0});
}

void Replicator::handle(const PeerId& from, const PullMsg& m) {
  if (m.whole_state || m.as_state) return answer_with_state(from, m);
  crdt::CausalContext missing = applied_.minus(to_context(m.applied));
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
      queue(from, DeltaMsg{e->origin, e->lo, e->hi, e->bytes, e->signature});
      ++stats_.deltas_relayed;
    }
    return;
  }
  answer_with_state(from, m);
}

void Replicator::answer_with_state(const PeerId& from, const PullMsg& m) {
  // A whole state is costly to build: to one peer at most once per first-pull patience (an
  // honest puller waits at least that long before asking again).
  Peer& p = peers_[from];
  if (p.last_state_answer_ns >= 0 && now_ - p.last_state_answer_ns < opt_.pull_first_timeout_ns) {
    ++stats_.state_answers_throttled;
    return;
  }
  p.last_state_answer_ns = now_;
  ++stats_.pulls_answered_with_state;
  std::vector<std::uint8_t> state = graph::encode(m.whole_state ? g_.state() : g_.state_diff(to_context(m.context)));
  const std::size_t chunk = std::clamp<std::size_t>(opt_.chunk_bytes, 1024, opt_.limits.max_chunk_bytes);
  const std::uint64_t count = std::max<std::uint64_t>(1, (state.size() + chunk - 1) / chunk);
  if (count > opt_.limits.max_chunks) {
    return reject(make_error(ErrorCode::kTooLarge, "pull from " + from.to_string() + ": this replica's state (" +
                                                       std::to_string(state.size()) + " bytes) exceeds what one "
                                                       "transfer may carry"));
  }
  const RangeList applied = to_ranges(applied_);
  for (std::uint64_t i = 0; i < count; ++i) {
    StateMsg s;
    s.request = m.request;
    s.index = i;
    s.count = count;
    if (i == 0) s.applied = applied;
    std::size_t begin = i * chunk, end = std::min(state.size(), begin + chunk);
    s.chunk = std::make_shared<const std::vector<std::uint8_t>>(state.begin() + begin, state.begin() + end);
    queue(from, std::move(s));
  }
}

void Replicator::handle(const PeerId& from, const StateMsg& m) {
  // Only the transfer answering our outstanding pull is assembled: nobody can make this replica
  // hold a state it did not ask for.
  if (!pulling_ || !(pull_target_ == from) || m.request != pull_request_) {
    ++stats_.states_unrequested;
    return;
  }
  Reassembly& ra = state_;
  if (!ra.active || ra.count != m.count) {
    ra = Reassembly{};
    ra.active = true;
    ra.count = m.count;
    ra.started_ns = now_;
    ra.chunks.resize(m.count);
  }
  if (ra.chunks[m.index]) return;  // duplicate
  if (ra.bytes + m.chunk->size() > opt_.max_state_bytes) {
    state_ = Reassembly{};
    return reject(make_error(ErrorCode::kTooLarge, "state from " + from.to_string() + " exceeds max_state_bytes (" +
                                                       std::to_string(opt_.max_state_bytes) + ")"));
  }
  pull_sent_ns_ = now_;  // progress: the pull is alive
  peers_[from].pull_failures = 0;
  ra.chunks[m.index] = m.chunk;
  ++ra.received;
  ra.bytes += m.chunk->size();
  if (m.index == 0) ra.applied = to_context(m.applied);
  if (ra.received < ra.count) return;
  pull_timeouts_in_a_row_ = 0;
  std::vector<std::uint8_t> all;
  all.reserve(ra.bytes);
  for (const auto& c : ra.chunks) all.insert(all.end(), c->begin(), c->end());
  crdt::CausalContext applied = std::move(ra.applied);
  state_ = Reassembly{};
  pulling_ = false;
  Status s = graph::decode(all, scratch_);
  if (!s.ok()) return reject(make_error(s.error().code, "state from " + from.to_string() + ": " + s.error().message));
  if (scratch_.kind != graph::GraphDelta::Kind::kState)
    return reject(make_error(ErrorCode::kMalformed, "state from " + from.to_string() + ": not a state"));
  if (admission_ != nullptr)
    if (Status a = admission_->admit_state(from, scratch_); !a.ok()) {
      ++stats_.states_refused;
      peers_[from].state_refused = true;
      return reject(make_error(ErrorCode::kPermissionDenied, "state from " + from.to_string() + " refused: " + a.error().message));
    }
  g_.merge(scratch_);
  ++state_version_;
  applied_.join(applied);
  if (journal_ != nullptr) journal_->state(all, applied);
  // A state may carry deltas forged under our name: our next numbers go beyond them.
  skip_own_numbers_to(applied_.max_counter(self_));
  ++stats_.states_applied;
  stats_.state_bytes_received += all.size();
  gap_pending_ = false;
  if (opt_.sample_ns > 0 && opt_.sample_bytes_per_s > 0) {
    const double wait_s = static_cast<double>(all.size()) / static_cast<double>(opt_.sample_bytes_per_s);
    next_sample_ = std::max(next_sample_, now_ + static_cast<std::int64_t>(wait_s * 1e9));
  }
}

void Replicator::handle(const PeerId& from, const ByeMsg&) {
  Peer& p = peers_[from];
  mark_left(p);
  p.said_bye = true;
}

// ------------------------------------------------------------------ buffer

void Replicator::remember(const PeerId& origin, std::uint64_t lo, std::uint64_t hi, Bytes bytes, Bytes signature) {
  auto& idx = buffer_index_[origin];
  if (idx.count(lo)) return;
  buffer_bytes_ += bytes->size();
  buffer_.push_back(Buffered{origin, lo, hi, std::move(bytes), std::move(signature)});
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

void Replicator::restore(const crdt::CausalContext& applied) {
  applied_.join(applied);
  seq_ = std::max(seq_, applied_.max_counter(self_));
}

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
  // discovering it); patience doubles with every timeout in a row, up to pull_timeout_ns. A peer
  // that leaves several pulls in a row unanswered while its summaries claim more is suspected
  // of claiming what it does not have: its summaries are ignored for a while.
  const std::int64_t patience =
      std::min(opt_.pull_timeout_ns, opt_.pull_first_timeout_ns << std::min(pull_timeouts_in_a_row_, 20));
  if (pulling_ && now_ - pull_sent_ns_ > patience) {
    pulling_ = false;
    last_failed_target_ = pull_target_;
    ++stats_.pulls_timed_out;
    ++pull_timeouts_in_a_row_;
    state_ = Reassembly{};
    if (auto it = peers_.find(pull_target_); it != peers_.end() && it->second.info.alive) {
      Peer& p = it->second;
      // Only a peer that keeps talking (its heartbeats arrive) yet never answers is suspected.
      const bool talking = now_ - p.info.last_heard_ns <= 2 * opt_.heartbeat_ns;
      if (++p.pull_failures >= opt_.suspect_after_timeouts && talking && p.suspect_until <= now_) {
        p.suspect_until = now_ + opt_.suspect_ns;
        p.pull_failures = 0;
        ++stats_.suspects;
        if (error_cb_) error_cb_(make_error(ErrorCode::kRefused, "peer " + p.info.id.to_string() + " ('" + p.info.name + "') left " +
                                                   std::to_string(opt_.suspect_after_timeouts) +
                                                   " pulls in a row unanswered while claiming changes this replica "
                                                   "lacks: its summaries are ignored for " +
                                                   std::to_string(opt_.suspect_ns / 1'000'000) + " ms"));
      }
    }
  }
  for (auto it = peers_.begin(); it != peers_.end();) {
    Peer& p = it->second;
    if (p.info.alive && now_ - p.info.last_heard_ns > opt_.lease_ns) mark_left(p);
    // Forget peers gone for long (bounded memory); a clean goodbye is kept as long, so that
    // its late packets stay ignored.
    if (!p.info.alive && now_ - p.info.last_heard_ns > 10 * opt_.lease_ns) {
      peer_ranges_ -= p.applied.range_count();
      it = peers_.erase(it);
    } else {
      ++it;
    }
  }
  if (state_.active && now_ - state_.started_ns > 4 * opt_.pull_timeout_ns) state_ = Reassembly{};
  const bool may_pull = opt_.sample_ns == 0 || now_ >= next_sample_;
  if (!pulling_ && may_pull) {
    const PeerId* pick = nullptr;
    for (const auto& [id, p] : peers_) {
      if (!counts(p) || !behind(p)) continue;
      if (pick == nullptr || *pick == last_failed_target_) pick = &id;
    }
    if (pick) {
      pull_from(*pick);
      if (opt_.sample_ns > 0) next_sample_ = now_ + opt_.sample_ns;
    } else if (gap_pending_ && now_ - gap_since_ns_ >= opt_.gap_grace_ns) {
      if (peer_alive(gap_peer_)) pull_from(gap_peer_);
      gap_pending_ = false;
    }
  }
  if (started_ && now_ >= next_heartbeat_) {
    const bool digest_due = opt_.digest_every_ns > 0 && now_ >= next_digest_;
    if (digest_due) next_digest_ = now_ + opt_.digest_every_ns;
    send_summary(digest_due);
    trim_buffer();
    next_heartbeat_ = now_ + opt_.heartbeat_ns;
  }
  send_queued();
}

}  // namespace quiver::agents
