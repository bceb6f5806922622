// Replicator, robot teams (docs/teams.md): what holds across a gateway. A replica whose peer is one
// side of a gateway (bridge.h) counts that peer's acknowledgement of a claim only once it vouches
// for every replica behind it (hold queries and answers, kHoldQuery/kHolds), and it knows a
// replica behind the gateway as alive while the gateway says so (kBehind): a lock held by
// another robot's agent neither looks expired nor is granted to two robots at once.

#include <algorithm>
#include <limits>

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
  p.holds.push_back(Peer::Held{origin, 0, -1});
  return p.holds.back();
}

std::uint64_t Replicator::held(const Peer& p, const PeerId& origin) const {
  std::uint64_t n = 0;
  for (const auto& h : p.holds)
    if (h.origin == origin) n = h.n;
  // A replica that is no gateway acknowledges our own numbers exactly in every addressed beat.
  if (origin == self_ && !p.info.gateway) n = std::max(n, p.your_seq);
  return n;
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
    const std::uint64_t n = held(p, origin);
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
      if (m.subject_seq <= h.n) break;
      h.n = m.subject_seq;
      if (holds_cb_) holds_cb_(m.subject);
      break;
    }
    case Beat::kBehind:
      for (const Rumor& r : m.rumors) {
        if (r.peer == self_ || peers_.count(r.peer) != 0) continue;  // one we hear ourselves
        if (r.status == Liveness::kDead) {
          if (auto it = remote_.find(r.peer); it != remote_.end() && it->second.via == from) remote_.erase(it);
        } else if (remote_.size() < opt_.max_peers || remote_.count(r.peer) != 0) {
          remote_[r.peer] = Behind{from, now_};
        }
      }
      break;
    default: break;
  }
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
  std::vector<Rumor> news;
  std::vector<PeerId> gone;
  std::set_difference(members.begin(), members.end(), behind_out_.begin(), behind_out_.end(),
                      std::back_inserter(gone));
  for (const PeerId& id : gone) news.push_back(Rumor{id, 0, Liveness::kAlive});
  gone.clear();
  std::set_difference(behind_out_.begin(), behind_out_.end(), members.begin(), members.end(),
                      std::back_inserter(gone));
  for (const PeerId& id : gone) news.push_back(Rumor{id, 0, Liveness::kDead});
  behind_out_ = std::move(members);
  send_behind(std::move(news));
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

void Replicator::send_behind(std::vector<Rumor> news) {
  if (!opt_.gateway || !started_) return;
  const std::size_t per_beat = std::max<std::size_t>(1, std::min<std::size_t>(opt_.limits.max_rumors, 32));
  for (std::size_t i = 0; i < news.size(); i += per_beat) {
    SummaryMsg m = beat(Beat::kBehind, PeerId{});
    m.rumors.assign(news.begin() + static_cast<long>(i),
                    news.begin() + static_cast<long>(std::min(news.size(), i + per_beat)));
    queue(PeerId{}, std::move(m));
  }
}

// Every rediscover_ns / 2 a gateway says again who is behind it (a lost change is repaired, a
// newcomer learns them); a peer forgets what it has not heard again for three of those periods.
void Replicator::behind_tick() {
  const std::int64_t period = std::max<std::int64_t>(opt_.rediscover_ns / 2, opt_.probe_ns);
  if (!askers_.empty() && askers_version_ != state_version_) check_askers(nullptr);
  if (opt_.gateway && now_ >= next_behind_ns_) {
    next_behind_ns_ = now_ + period;
    std::vector<Rumor> all;
    for (const PeerId& id : behind_out_) all.push_back(Rumor{id, 0, Liveness::kAlive});
    send_behind(std::move(all));
  }
  std::erase_if(remote_, [&](const auto& e) { return now_ - e.second.heard_ns > 3 * period || !peer_alive(e.second.via); });
}

}  // namespace quiver::agents
