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

PeerDetail::Held& Replicator::held_entry(Peer& p, const PeerId& origin) {
  std::vector<PeerDetail::Held>& holds = d(p).holds;
  for (auto& h : holds)
    if (h.origin == origin) return h;
  if (holds.size() >= kMaxHolds) {
    // The entry asked about longest ago goes: its claim is long settled or given up.
    auto oldest = std::min_element(holds.begin(), holds.end(),
                                   [](const PeerDetail::Held& a, const PeerDetail::Held& b) { return a.asked_ns < b.asked_ns; });
    holds.erase(oldest);
  }
  holds.push_back(PeerDetail::Held{origin, 0, -1, 0});
  return holds.back();
}

std::uint64_t Replicator::held(const Peer& p, const PeerId& origin) const {
  std::uint64_t n = 0;
  const PeerDetail& pd = seen(p);
  for (const auto& h : pd.holds)
    if (h.origin == origin && (!pd.gateway || h.generation == pd.behind_generation)) n = h.n;
  // A replica that is no gateway acknowledges our own numbers exactly in every addressed beat.
  if (origin == self_ && !pd.gateway) n = std::max(n, p.your_seq);
  return n;
}

int Replicator::generation_heard(const PeerId& peer) const {
  auto it = peers_.find(peer);
  return it != peers_.end() && seen(it->second).gateway ? seen(it->second).behind_generation : -1;
}

bool Replicator::member_alive(const PeerId& peer) const {
  if (peer_alive(peer)) return true;
  auto it = remote_.find(peer);
  return it != remote_.end() && peer_alive(it->second.via);
}

bool Replicator::newer_from_gateway(bool ahead, std::int64_t taken_ns) const {
  // A beat overtakes another by far less than a probe period; a gateway's list comes again every
  // period, and its generation with each of its beats.
  return ahead || taken_ns < 0 || now_ - taken_ns >= opt_.probe_ns;
}

std::uint64_t Replicator::peers_hold_upto(const PeerId& origin, std::uint64_t wanted) {
  std::uint64_t least = std::numeric_limits<std::uint64_t>::max();
  for (auto&& [id, p] : peers_) {
    if (!p.alive || p.observer || id == origin) continue;
    // A gateway's answer counts once we hold what it holds: claims made behind it reach our side
    // before our vouch does (as a peer's own deltas reach a claimant before its ack: repair_own()).
    const std::uint64_t n = seen(p).gateway && behind(p) ? 0 : held(p, origin);
    least = std::min(least, n);
    if (n >= wanted) continue;
    PeerDetail::Held& h = held_entry(p, origin);
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
      PeerDetail::Held& h = held_entry(p, m.subject);
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
      if (m.rumors.empty() || !(m.rumors[0].peer == from)) break;
      if (m.rumors[0].life < seen(p).behind_version && !newer_from_gateway(false, seen(p).behind_version_ns)) break;
      d(p).behind_version = m.rumors[0].life;
      d(p).behind_version_ns = now_;
      const auto entries = std::span<const Rumor>(m.rumors).subspan(1);
      if (m.subject == from)  // the whole list, in one beat: whom it no longer names has gone
        std::erase_if(remote_, [&](const auto& e) {
          return e.second.via == from && std::none_of(entries.begin(), entries.end(), [&](const Rumor& r) {
                   return r.peer == e.first && r.status != Liveness::kDead;
                 });
        });
      // Who they are: the gateway's robot, then one "ROBOT<tab>NAME" line per entry (an older
      // gateway's beat, or one whose lines do not match its entries, says nothing of them).
      std::vector<std::string_view> lines;
      for (std::string_view rest = m.name;;) {
        const auto nl = rest.find('\n');
        lines.push_back(rest.substr(0, nl));
        if (nl == std::string_view::npos) break;
        rest.remove_prefix(nl + 1);
      }
      const bool said = lines.size() == entries.size() + 1;
      if (said && (gateway_robots_.count(from) != 0 || gateway_robots_.size() < kMaxGateways))
        gateway_robots_[from] = std::string(lines[0]);
      for (std::size_t k = 0; k < entries.size(); ++k) {
        const Rumor& r = entries[k];
        // One we hear ourselves is no replica behind it; an entry marked gone names none.
        if (r.status == Liveness::kDead || r.peer == self_ || peers_.count(r.peer) != 0) continue;
        if (remote_.count(r.peer) == 0 && remote_.size() >= opt_.max_peers) continue;
        Behind& b = remote_[r.peer];
        b.via = from;
        b.heard_ns = now_;
        if (!said) continue;
        const std::string_view l = lines[k + 1];
        const auto tab = l.find('\t');
        if (tab == std::string_view::npos) continue;
        b.robot = std::string(l.substr(0, tab));
        // A name is taken only if it hashes to the replica's id (as a beat's own name is).
        if (remember_name(r.peer, std::string(l.substr(tab + 1)))) b.name = std::string(l.substr(tab + 1));
        if (!b.robot.empty() && (robots_.count(r.peer.agent) != 0 || robots_.size() < 4 * opt_.max_peers))
          robots_[r.peer.agent] = b.robot;
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

void Replicator::set_members_behind(std::vector<Member> members) {
  const auto by_id = [](const Member& a, const Member& b) { return a.id < b.id; };
  std::sort(members.begin(), members.end(), by_id);
  members.erase(std::unique(members.begin(), members.end(), [](const Member& a, const Member& b) { return a.id == b.id; }),
                members.end());
  if (members == behind_out_) return;
  // Replicas came: what we vouched for before does not cover them (the generation says so).
  if (!std::includes(behind_out_.begin(), behind_out_.end(), members.begin(), members.end(), by_id)) ++behind_generation_;
  ++behind_version_;
  behind_out_ = std::move(members);
  tell_behind(PeerId{});
  send_queued();
}

std::vector<Member> Replicator::members_here() const {
  std::vector<Member> out;
  const std::string here = robot_here();
  for (const auto& [id, p] : peers_)
    if (p.alive && !p.observer && !seen(p).gateway) out.push_back(Member{id, seen(p).name, here, PeerId{}});
  for (const auto& [id, b] : remote_)
    if (peer_alive(b.via)) out.push_back(Member{id, b.name, b.robot, PeerId{}});
  return out;
}

std::vector<Member> Replicator::remote_members() const {
  std::vector<Member> out;
  for (const auto& [id, b] : remote_)
    if (peer_alive(b.via)) out.push_back(Member{id, name_of(id), b.robot, b.via});
  return out;
}

std::string Replicator::robot_here() const {
  if (!opt_.robot.empty()) return opt_.robot;
  for (const auto& [id, robot] : gateway_robots_)
    if (peer_alive(id) && !robot.empty()) return robot;
  return {};
}

std::string Replicator::robot_of(const PeerId& id) const {
  if (auto it = remote_.find(id); it != remote_.end() && !it->second.robot.empty()) return it->second.robot;
  if (id == self_ || peers_.count(id) != 0) {
    if (auto g = gateway_robots_.find(id); g != gateway_robots_.end() && !g->second.empty()) return g->second;
    return robot_here();
  }
  if (auto it = robots_.find(id.agent); it != robots_.end()) return it->second;
  return {};
}

// Always the whole list, versioned: a receiver takes a list no older than the last it took, so a
// reordered one changes nothing. Each beat: a header (ourselves, with the list's version), then
// up to per_beat entries. A list that fits one beat says it is whole (its subject is the sender):
// a receiver then forgets whom it no longer names, even when it missed the list that left them
// out. An empty list is one such beat. The beat's name field carries who they are: our robot,
// then one line per entry, "ROBOT<tab>NAME" (docs/teams.md); a beat ends early rather than let
// it outgrow the name limit.
void Replicator::tell_behind(const PeerId& to) {
  if (!opt_.gateway || !started_) return;
  const std::size_t per_beat = std::max<std::size_t>(1, std::min<std::size_t>(opt_.limits.max_rumors, 32) - 1);
  // (A name or robot that holds a line break or a tab would break the lines: sent as unknown.)
  const auto plain = [](const std::string& s) { return s.find_first_of("\n\t") == std::string::npos ? s : std::string(); };
  const auto line = [&](const Member& e) { return "\n" + plain(e.robot) + "\t" + plain(e.name); };
  const std::size_t n = behind_out_.size();
  std::size_t i = 0;
  do {
    SummaryMsg m = beat(Beat::kBehind, to, /*rumors=*/false);
    m.name = robot_here();
    m.rumors.push_back(Rumor{self_, behind_version_, Liveness::kAlive});
    std::size_t k = i;
    for (; k < n && k - i < per_beat; ++k) {
      std::string l = line(behind_out_[k]);
      if (k > i && m.name.size() + l.size() > opt_.limits.max_name_bytes) break;
      // One entry's line alone over the limit: listed unnamed.
      if (m.name.size() + l.size() > opt_.limits.max_name_bytes) l = "\n\t";
      m.name += l;
      m.rumors.push_back(Rumor{behind_out_[k].id, 0, Liveness::kAlive});
    }
    if (i == 0 && k == n) m.subject = self_;
    queue(to, std::move(m));
    i = k;
  } while (i < n);
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
