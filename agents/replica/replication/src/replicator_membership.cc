// Replicator membership: peers heard from, lost and gone (bye), what the live peers are
// believed to hold, and how much of what it records of them a replica keeps (trim_details()).

#include "quiver/agents/replica/replication/replicator.h"

#include <algorithm>

namespace quiver::agents::inline replica {

Replicator::Peer* Replicator::heard_from(const PeerId& from) {
  auto it = peers_.find(from);
  if (it == peers_.end()) {
    if (peers_.size() >= opt_.max_peers) {
      // Make room from peers that are gone; a table full of live ones refuses the newcomer.
      for (auto g = peers_.begin(); g != peers_.end() && peers_.size() >= opt_.max_peers;) {
        if (!g->second.alive) {
          peer_ranges_ -= seen(g->second).applied.range_count();
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
    it->second.id = from;
  }
  Peer& p = it->second;
  if (p.said_bye) return nullptr;  // a late message of an incarnation that left cleanly
  d(p).heard_ns = now_;
  // Gossip: a peer declared gone comes back only when it refutes (a higher life, handle_gossip()).
  if (!p.alive && !(opt_.gossip && p.status == Liveness::kDead)) {
    p.alive = true;
    retire_older_incarnations(from);
    if (membership_cb_ && p.announced) membership_cb_(Membership::kJoined, info_of(p));
  }
  return &p;
}

void Replicator::mark_left(Peer& p) {
  if (!p.alive) return;
  p.alive = false;
  if (state_.active && pull_target_ == p.id) state_ = Reassembly{};
  if (pulling_ && pull_target_ == p.id) pulling_ = false;
  if (membership_cb_ && p.announced) membership_cb_(Membership::kLeft, info_of(p));
}

void Replicator::on_peer_lost(const PeerId& peer, bool gone) {
  auto it = peers_.find(peer);
  if (it == peers_.end()) return;
  mark_left(it->second);
  if (gone) it->second.said_bye = true;
}

// A new incarnation of an agent means the old one is gone.
void Replicator::retire_older_incarnations(const PeerId& peer) {
  for (auto&& [id, other] : peers_)
    if (other.alive && id.agent == peer.agent && id.incarnation < peer.incarnation) mark_left(other);
}

// Remembered past the peer's departure (deltas it made keep arriving through others), but only
// a name that hashes to the id it came with: nobody can name another agent's changes.
bool Replicator::remember_name(const PeerId& from, const std::string& name) {
  if (name.empty() || fnv1a64(name) != from.agent) return false;
  // With gossip, at most kMaxNames are kept (docs/protocol.md, "Protocol state per replica"): a new
  // one takes the place of the next in id order (a choice every replica makes alike, and no clock).
  const std::size_t cap = opt_.gossip ? kMaxNames : 4 * opt_.max_peers;
  if (names_.count(from.agent) == 0 && names_.size() >= cap) {
    if (!opt_.gossip) return true;
    auto next = names_.upper_bound(from.agent);
    names_.erase(next == names_.end() ? names_.begin() : next);
  }
  names_.emplace(from.agent, name);
  return true;
}

std::vector<PeerInfo> Replicator::peers() const {
  std::vector<PeerInfo> out;
  for (const auto& [id, p] : peers_) {
    out.push_back(info_of(p));
    // Gossip: a peer some replica failed to probe is suspect until it refutes (or is declared
    // gone): what a lease running out tells with all-to-all summaries, but sooner.
    out.back().suspect = seen(p).suspect_until > now_ || (opt_.gossip && p.status == Liveness::kSuspect);
  }
  return out;
}

std::size_t Replicator::live_peer_count() const {
  std::size_t n = 0;
  for (const auto& [id, p] : peers_) n += p.alive ? 1 : 0;
  return n;
}

bool Replicator::peer_alive(const PeerId& peer) const {
  auto it = peers_.find(peer);
  return it != peers_.end() && it->second.alive;
}

bool Replicator::all_peers_hold(const PeerId& origin, std::uint64_t lo, std::uint64_t hi) const {
  for (const auto& [id, p] : peers_) {
    if (!p.alive) continue;
    // Gossip: a peer acknowledges this replica's own numbers (your_seq), and holds others' when
    // its reported set is ours or it told us its whole set. A gateway acknowledges ours only for
    // every replica behind it too (kHolds, replicator_behind.cc).
    const PeerDetail& pd = seen(p);
    bool holds;
    if (!opt_.gossip)
      holds = pd.applied.includes(origin, lo, hi);
    else if (origin == self_ && pd.gateway)
      holds = held(p, self_) >= hi;
    else
      holds = (origin == self_ && p.your_seq >= hi) ||
              (pd.report_ns >= 0 && pd.hash == set_hash() && applied_.includes(origin, lo, hi)) ||
              (pd.full && pd.applied.includes(origin, lo, hi));
    if (!holds) return false;
  }
  return true;
}

bool Replicator::peers_hold_all() const {
  for (const auto& [id, p] : peers_) {
    if (!counts(p) || p.observer) continue;
    const PeerDetail& pd = seen(p);
    const bool holds = opt_.gossip ? (pd.report_ns >= 0 && pd.hash == set_hash()) || pd.covered == set_hash()
                                   : pd.applied.includes(applied_);
    if (!holds) return false;
  }
  return true;
}

// A live peer whose summaries are believed (not suspected of claiming what it never delivers).
bool Replicator::counts(const Peer& p) const { return p.alive && seen(p).suspect_until <= now_; }

bool Replicator::synced() const {
  bool any = false;
  for (const auto& [id, p] : peers_) {
    if (!counts(p)) continue;
    any = true;
    if (behind(p)) return false;
  }
  return any && !state_.active && !(opt_.gossip && pulling_);
}

// What a replica records of the peers it deals with is kept for the kMaxDetails used most recently,
// and for every peer some rule waits on: the details that hold an offered set, a refused state,
// a gateway's holds and generations, pull or digest doubts, this replica's suspicion, or that name
// the peer being pulled from, probed, sent the digest or whose set differs. What goes is a report
// (hash, count, times) the peer's next beat gives again (docs/protocol.md).
void Replicator::trim_details() {
  // A replica handing over before it stops (offer_all()) keeps every report until it has left:
  // peers_hold_all() reads them all.
  if (offering_) return;
  peers_.trim_details(kMaxDetails, [this](const PeerId& id, const PeerDetail& pd) {
    if (pd.full || !pd.applied.empty() || pd.state_refused || pd.gateway || !pd.holds.empty() || pd.pull_failures > 0 ||
        pd.digest_mismatches > 0 || pd.suspect_until > now_)
      return true;
    if (((pulling_ || state_.active) && id == pull_target_) || (probe_sent_ns_ >= 0 && id == probe_target_) ||
        id == digest_to_ || (gap_pending_ && id == gap_peer_) || mismatched_.count(id) != 0)
      return true;
    auto it = peers_.find(id);
    return it != peers_.end() && it->second.my_suspicion;
  });
  // The (origin, seq) set's arrays keep at most an eighth more than they hold.
  applied_.shrink_to(applied_.replica_count() + applied_.replica_count() / 8);
}

void Replicator::handle(const PeerId& from, const ByeMsg&) {
  Peer& p = peers_[from];
  mark_left(p);
  p.said_bye = true;
}

}  // namespace quiver::agents
