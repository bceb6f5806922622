// Replicator, robot teams (docs/teams.md): what holds across a gateway. A replica whose peer is one
// side of a gateway (bridge.h) counts that peer's acknowledgement of a claim only once it vouches
// for every replica behind it (hold queries and answers, kHoldQuery/kHolds), and it knows a
// replica behind the gateway as alive while the gateway says so (kBehind): a lock held by
// another robot's agent neither looks expired nor is granted to two robots at once.

#include <algorithm>
#include <limits>
#include <span>

#include "quiver/agents/replica/replication/replicator.h"

namespace quiver::agents::inline replica {

Replicator::Peer::Held& Replicator::held_entry(Peer& p, const PeerId& origin) {
  for (auto& h : p.holds)
    if (h.origin == origin) return h;
  if (p.holds.size() >= kMaxHolds) {
    // The entry asked about longest ago goes: its claim is long settled or given up.
    auto oldest = std::min_element(p.holds.begin(), p.holds.end(),
                                   [](const Peer::Held& a, const Peer::Held& b) { return a.asked_ns < b.asked_ns; });
    p.holds.erase(oldest);
  }
  p.holds.push_back(Peer::Held{origin, 0, -1, 0});
  return p.holds.back();
}

std::uint64_t Replicator::held(const Peer& p, const PeerId& origin) const {
  std::uint64_t n = 0;
  for (const auto& h : p.holds)
    if (h.origin == origin && (!p.info.gateway || h.generation == p.behind_generation)) n = h.n;
  // A replica that is no gateway acknowledges our own numbers exactly in every addressed beat.
  if (origin == self_ && !p.info.gateway) n = std::max(n, p.your_seq);
  return n;
}

int Replicator::generation_heard(const PeerId& peer) const {
  auto it = peers_.find(peer);
  return it != peers_.end() && it->second.info.gateway ? it->second.behind_generation : -1;
}

bool Replicator::member_alive(const PeerId& peer) const {
  if (peer_alive(peer)) return true;
  auto it = remote_.find(peer);
  return it != remote_.end() && peer_alive(it->second.via);
}

std::uint64_t Replicator::peers_hold_upto(const PeerId& origin, std::uint64_t wanted) {
  std::uint64_t least = std::numeric_limits<std::uint64_t>::max();
  for (auto& [id, p] : peers_) {
    if (!p.info.alive || p.info.observer || id == origin) continue;
    // A gateway's answer counts once we hold what it holds: claims made behind it reach our side
    // before our vouch does (as a peer's own deltas reach a claimant before its ack: repair_own()).
    const std::uint64_t n = p.info.gateway && behind(p) ? 0 : held(p, origin);
    least = std::min(least, n);
    if (n >= wanted) continue;
    Peer::Held& h = held_entry(p, origin);
    if (h.asked_ns >= 0 && now_ - h.asked_ns < opt_.gap_grace_ns) continue;
    h.asked_ns = now_;
    send_hold(Beat::kHoldQuery, id, origin, wanted);
  }
  send_queued();
  return least;
}

std::uint64_t Replicator::vouch(const PeerId& origin, std::uint64_t wanted) {
  std::uint64_t n = origin == self_ ? seq_ : applied_.contiguous(origin);
  if (behind_) n = std::min(n, behind_(origin, std::min(n, wanted)));
  return n;
}

void Replicator::send_hold(Beat b, const PeerId& to, const PeerId& origin, std::uint64_t n) {
  SummaryMsg m = beat(b, to);
  m.subject = origin;
  m.subject_seq = n;
  queue(to, std::move(m));
}

void Replicator::handle_team_beat(const PeerId& from, Peer& p, const SummaryMsg& m) {
  switch (m.beat) {
    case Beat::kHoldQuery: {
      const std::uint64_t n = vouch(m.subject, m.subject_seq);
      if (n > 0) send_hold(Beat::kHolds, from, m.subject, n);
      if (n >= m.subject_seq) break;
      // Answered again when we (and what is behind us) hold more: check_askers().
      for (Asker& a : askers_)
        if (a.origin == m.subject && a.asker == from) {
          a.wanted = std::max(a.wanted, m.subject_seq);
          a.told = std::max(a.told, n);
          return;
        }
      if (askers_.size() >= kMaxAskers) askers_.erase(askers_.begin());
      askers_.push_back(Asker{m.subject, from, m.subject_seq, n, now_});
      break;
    }
    case Beat::kHolds: {
      Peer::Held& h = held_entry(p, m.subject);
      // An answer under another generation of the gateway replaces what it said before.
      if (m.generation == h.generation && m.subject_seq <= h.n) break;
      h.generation = m.generation;
      h.n = m.subject_seq;
      if (holds_cb_) holds_cb_(m.subject);
      break;
    }
    case Beat::kBehind: {
      // The first rumor names the gateway itself with the version of its list: a list older than
      // one already taken (reordered) changes nothing.
      if (m.rumors.empty() || !(m.rumors[0].peer == from) || m.rumors[0].life < p.behind_version) break;
      p.behind_version = m.rumors[0].life;
      const auto entries = std::span<const Rumor>(m.rumors).subspan(1);
      if (m.subject == from)  // the whole list, in one beat: whom it no longer names has gone
        std::erase_if(remote_, [&](const auto& e) {
          return e.second.via == from && std::none_of(entries.begin(), entries.end(), [&](const Rumor& r) {
                   return r.peer == e.first && r.status != Liveness::kDead;
                 });
        });
      for (const Rumor& r : entries) {
        // One we hear ourselves is no replica behind it; an entry marked gone names none.
        if (r.status == Liveness::kDead || r.peer == self_ || peers_.count(r.peer) != 0) continue;
        if (remote_.count(r.peer) != 0 || remote_.size() < opt_.max_peers) remote_[r.peer] = Behind{from, now_};
      }
      break;
    }
    default: break;
  }
}

void Replicator::ask_again() {
  if (claims_seq_ == 0 || want_acks_seq_ >= claims_seq_) return;
  want_acks_seq_ = claims_seq_;
  next_ack_request_ns_ = now_;
}

void Replicator::answer_holds(const PeerId& origin) {
  check_askers(&origin);
  send_queued();
}

void Replicator::check_askers(const PeerId* origin) {
  for (auto it = askers_.begin(); it != askers_.end();) {
    Asker& a = *it;
    // The asker asks again while it waits; an old question is dropped.
    const bool stale = now_ - a.since_ns > 4 * opt_.pull_timeout_ns || !peer_alive(a.asker);
    if (!stale && (origin == nullptr || a.origin == *origin)) {
      const std::uint64_t n = vouch(a.origin, a.wanted);
      if (n > a.told) {
        a.told = n;
        send_hold(Beat::kHolds, a.asker, a.origin, n);
      }
    }
    it = stale || a.told >= a.wanted ? askers_.erase(it) : std::next(it);
  }
  askers_version_ = state_version_;
}

void Replicator::set_members_behind(std::vector<PeerId> members) {
  std::sort(members.begin(), members.end());
  members.erase(std::unique(members.begin(), members.end()), members.end());
  if (members == behind_out_) return;
  // Replicas came: what we vouched for before does not cover them (the generation says so).
  if (!std::includes(behind_out_.begin(), behind_out_.end(), members.begin(), members.end())) ++behind_generation_;
  ++behind_version_;
  behind_out_ = std::move(members);
  tell_behind(PeerId{});
  send_queued();
}

std::vector<PeerId> Replicator::members_here() const {
  std::vector<PeerId> out;
  for (const auto& [id, p] : peers_)
    if (p.info.alive && !p.info.observer && !p.info.gateway) out.push_back(id);
  for (const auto& [id, b] : remote_)
    if (peer_alive(b.via)) out.push_back(id);
  return out;
}

// Always the whole list, versioned: a receiver takes a list no older than the last it took, so a
// reordered one changes nothing. Each beat: a header (ourselves, with the list's version), then
// up to per_beat entries. A list that fits one beat says it is whole (its subject is the sender):
// a receiver then forgets whom it no longer names, even when it missed the list that left them
// out. An empty list is one such beat.
void Replicator::tell_behind(const PeerId& to) {
  if (!opt_.gateway || !started_) return;
  const std::size_t per_beat = std::max<std::size_t>(1, std::min<std::size_t>(opt_.limits.max_rumors, 32) - 1);
  const std::size_t n = behind_out_.size();
  for (std::size_t i = 0; i == 0 || i < n; i += per_beat) {
    SummaryMsg m = beat(Beat::kBehind, to, /*rumors=*/false);
    if (n <= per_beat) m.subject = self_;
    m.rumors.push_back(Rumor{self_, behind_version_, Liveness::kAlive});
    for (std::size_t k = i; k < std::min(n, i + per_beat); ++k)
      m.rumors.push_back(Rumor{behind_out_[k], 0, Liveness::kAlive});
    queue(to, std::move(m));
  }
}

// Every probe period a gateway says again who is behind it (a lost change is repaired, a newcomer
// learns them); a peer forgets what it has not heard again for three of those periods.
void Replicator::behind_tick(bool sweep) {
  const std::int64_t period = opt_.probe_ns;
  if (!askers_.empty() && askers_version_ != state_version_) check_askers(nullptr);
  if (opt_.gateway && now_ >= next_behind_ns_) {
    next_behind_ns_ = now_ + period;
    tell_behind(PeerId{});
  }
  if (sweep)
    std::erase_if(remote_, [&](const auto& e) { return now_ - e.second.heard_ns > 3 * period || !peer_alive(e.second.via); });
}

}  // namespace quiver::agents
