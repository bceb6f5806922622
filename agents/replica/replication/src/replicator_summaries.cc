// Replicator summaries: what this replica holds (and its state digest) announced, and peers'
// summaries compared with it (digests checked, missing intervals pulled).

#include "quiver/agents/replica/replication/replicator.h"

#include <algorithm>

namespace quiver::agents::inline replica {

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
  if (digest == 0 || seen(p).state_refused || pulling_ || state_.active || pending_lo_ != 0 || !(seen(p).applied == applied_)) return;
  if (digest == state_digest()) {
    d(p).digest_mismatches = 0;
    return;
  }
  if (++d(p).digest_mismatches < 2) return;
  d(p).digest_mismatches = 0;
  ++stats_.divergences;
  equivocation("replica " + who(from) + " holds the same deltas as this one but another state: pulling its whole state");
  pull_from(from, true);
}

// A peer's whole (origin, seq) set, within the bound on all peers' ranges together.
bool Replicator::take_peer_set(const PeerId& from, Peer& p, crdt::CausalContext applied) {
  const std::size_t total = peer_ranges_ - seen(p).applied.range_count() + applied.range_count();
  if (total > opt_.max_peer_ranges) {
    reject(make_error(ErrorCode::kTooLarge, "summary from " + who(from) + ": " +
                                                std::to_string(applied.range_count()) +
                                                " ranges would exceed the peer table's limit"));
    return false;
  }
  peer_ranges_ = total;
  d(p).applied = std::move(applied);
  return true;
}

void Replicator::handle(const PeerId& from, const SummaryMsg& m) {
  Peer& p = peers_[from];
  if (opt_.gossip) return handle_gossip(from, p, m);
  if (!take_peer_set(from, p, to_context(m.applied))) return;
  const bool first = !p.announced;
  d(p).name = m.name;
  p.named = !m.name.empty();
  p.observer = m.observer;
  remember_name(from, m.name);
  if (first) {
    p.announced = true;
    if (membership_cb_ && p.alive) membership_cb_(Membership::kJoined, info_of(p));
    send_summary();  // let a newcomer learn about us without waiting a heartbeat
  }
  if (!behind(p)) d(p).pull_failures = 0;  // it holds nothing we lack: no claim to doubt
  if (pulling_ && pull_target_ == from && !behind(p)) {  // caught up with it: the pull is done
    pulling_ = false;
    pull_timeouts_in_a_row_ = 0;
  }
  // A sampling observer pulls on its own clock (tick()), not at every summary.
  if (!pulling_ && opt_.sample_ns == 0 && counts(p) && behind(p)) pull_from(from);
  if (counts(p)) check_digest(from, p, m.digest);
}

}  // namespace quiver::agents
