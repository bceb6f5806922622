// Replicator gossip membership (ReplicatorOptions::gossip): constant-size beats to one peer per
// probe period (SWIM-style probes, indirect probes, suspicion and refutation), membership rumors
// piggybacked on them, (origin, seq) sets compared by hash and count and exchanged only when they
// differ, acknowledgements asked for only when a lock claim needs them, and the relay buffer
// trimmed by age and acknowledgement. docs/protocol.md, "Membership and anti-entropy without
// all-to-all heartbeats", explains why each piece is there.

#include <algorithm>
#include <bit>

#include "quiver/agents/replica/replication/replicator.h"

namespace quiver::agents::inline replica {
namespace {
const std::string kNoName;
}  // namespace

void Replicator::refresh_set_hash() const {
  if (hash_version_ == state_version_) return;
  Hasher h(0x5e7);
  std::uint64_t n = 0;
  applied_.for_each_range([&](const PeerId& r, std::uint64_t lo, std::uint64_t hi) {
    h.u64(r.agent).u64(r.incarnation).u64(lo).u64(hi);
    n += hi - lo + 1;
  });
  set_hash_ = h.h64() | 1;  // never 0 (0: not sent)
  set_count_ = n;
  hash_version_ = state_version_;
}

std::int64_t Replicator::suspect_timeout() const {
  if (opt_.suspect_timeout_ns > 0) return opt_.suspect_timeout_ns;
  return std::max(opt_.lease_ns, 3 * opt_.probe_ns);
}

SummaryMsg Replicator::beat(Beat b, const PeerId& to, bool rumors) {
  SummaryMsg m;
  // The name goes in every hello, and in another beat only to a peer we have not named ourselves
  // to yet: it is most of a beat's variable size.
  const auto known = to.is_null() ? peers_.end() : peers_.find(to);
  // (A kBehind beat's name field lists the replicas behind a gateway instead.)
  if (b != Beat::kBehind && (b == Beat::kHello || to.is_null() || known == peers_.end() || !known->second.told_name ||
                             !known->second.named)) {
    m.name = opt_.name;
    if (known != peers_.end()) known->second.told_name = true;
  }
  m.observer = opt_.observer;
  m.gateway = opt_.gateway;
  m.generation = static_cast<std::uint8_t>(behind_generation_ & 63);
  m.beat = b;
  m.life = life_;
  m.set_hash = set_hash();
  m.count = set_count();
  if (!to.is_null()) {
    m.your_seq = applied_.contiguous(to);
    if (auto it = peers_.find(to); it != peers_.end()) {
      const PeerDetail& pd = seen(it->second);
      if (pd.full && applied_.includes(pd.applied)) m.covered = pd.full_hash;
    }
  }
  // The state digest goes to the peers in turn (next_digest_target()), one a period: the first
  // beat after it fell due to whoever came first would reach the same peer every period when
  // the probes keep step with it, and a divergence with the others would never show.
  if (digest_due_ && pending_lo_ == 0 && !to.is_null() && to == digest_to_) {
    m.digest = state_digest();
    digest_due_ = false;
  }
  if (!rumors) return m;
  // Rumors: a suspicion of the receiver first (so that it can refute), then the others, each
  // until it has been sent its number of times.
  if (!to.is_null())
    if (auto it = peers_.find(to); it != peers_.end() && it->second.status != Liveness::kAlive)
      m.rumors.push_back(Rumor{to, it->second.life, it->second.status});
  for (auto& s : rumors_) {
    if (m.rumors.size() >= opt_.rumors_per_beat) break;
    if (s.rumor.peer == to && s.rumor.status != Liveness::kAlive) continue;  // already first
    m.rumors.push_back(s.rumor);
    --s.left;
  }
  std::erase_if(rumors_, [](const Spreading& s) { return s.left <= 0; });
  return m;
}

void Replicator::send_beat(Beat b, const PeerId& to, const PeerId& subject) {
  SummaryMsg m = beat(b, to);
  m.subject = subject;
  queue(to, std::move(m));
}

void Replicator::send_full(const PeerId& to) {
  SummaryMsg m = beat(Beat::kFull, to);
  m.applied = to_ranges(applied_);
  queue(to, std::move(m));
}

void Replicator::spread(const Rumor& r) {
  const int repeats =
      opt_.rumor_repeats * std::max(1, static_cast<int>(std::bit_width(static_cast<std::uint64_t>(peers_.size()) + 1)));
  // One rumor per peer: a newer one replaces an older.
  std::erase_if(rumors_, [&](const Spreading& s) { return s.rumor.peer == r.peer; });
  rumors_.push_back(Spreading{r, repeats});
  // Bounded: the oldest news goes first.
  const std::size_t cap = std::max<std::size_t>(64, 4 * opt_.rumors_per_beat);
  if (rumors_.size() > cap) rumors_.erase(rumors_.begin(), rumors_.begin() + static_cast<long>(rumors_.size() - cap));
}

void Replicator::suspect(Peer& p) {
  if (!p.alive || p.status != Liveness::kAlive) return;
  p.status = Liveness::kSuspect;
  p.my_suspicion = true;
  d(p).suspect_since = now_;
  ++stats_.suspicions;
  spread(Rumor{p.id, p.life, Liveness::kSuspect});
}

void Replicator::declare_dead(Peer& p) {
  p.status = Liveness::kDead;
  p.my_suspicion = false;
  mismatched_.erase(p.id);
  if (p.alive) ++stats_.declared_gone;
  mark_left(p);
  spread(Rumor{p.id, p.life, Liveness::kDead});
}

// SWIM's rules, with the life as incarnation: news about a higher life wins; for the same life,
// dead beats suspect beats alive. A replica suspected or declared gone refutes with a higher life.
void Replicator::hear_rumor(const Rumor& heard) {
  Rumor r = heard;
  r.life = PeerRecord::clamp_life(r.life);  // lives are kept in 32 bits (peer_table.h)
  if (r.peer == self_) {
    if (r.status != Liveness::kAlive && r.life >= life_) {
      life_ = std::min(r.life + 1, PeerRecord::kMaxLife);
      ++stats_.refutations;
      spread(Rumor{self_, life_, Liveness::kAlive});
    }
    return;
  }
  auto it = peers_.find(r.peer);
  if (it == peers_.end()) {
    // A peer only heard of: known alive (it must acknowledge claims too), named when it talks.
    if (r.status != Liveness::kAlive) return;
    Peer* p = add_peer(r.peer);
    if (p == nullptr) return;  // the table is full
    p->life = static_cast<std::uint32_t>(r.life);
    spread(r);
    return;
  }
  Peer& p = it->second;
  if (p.said_bye) return;
  const auto rank = [](Liveness s) { return static_cast<int>(s); };
  const bool news = r.life > p.life || (r.life == p.life && rank(r.status) > rank(p.status));
  if (!news) return;
  p.life = static_cast<std::uint32_t>(r.life);
  switch (r.status) {
    case Liveness::kAlive:
      p.status = Liveness::kAlive;
      p.my_suspicion = false;
      if (!p.alive) {
        p.alive = true;
        d(p).heard_ns = now_;
        if (membership_cb_ && p.announced) membership_cb_(Membership::kJoined, info_of(p));
      }
      break;
    case Liveness::kSuspect:
      // Someone else's suspicion: noted and passed on; only the suspecter declares it gone.
      p.status = Liveness::kSuspect;
      p.my_suspicion = false;
      break;
    case Liveness::kDead:
      p.status = Liveness::kDead;
      p.my_suspicion = false;
      mismatched_.erase(p.id);
      mark_left(p);
      break;
  }
  spread(r);
}

bool Replicator::behind(const Peer& p) const {
  const PeerDetail& pd = seen(p);
  if (!opt_.gossip) return !applied_.includes(pd.applied);  // its last summary holds more
  if (pd.full && !applied_.includes(pd.applied)) return true;
  if (pd.report_ns < 0 || pd.hash == set_hash()) return false;
  // It holds more changes of origins other than this replica than this replica does: at least
  // one of them is missing here. Unlike the counts, this holds while this replica keeps changing
  // (its own changes in flight to the peer make the peer's count lag).
  if (pd.others > set_count() - std::min(set_count(), applied_.contiguous(self_))) return true;
  // Its set differs: it may hold what we lack if it holds more, or as many but others, and
  // nothing changed here since it said so (a delta in flight makes sets differ for a moment).
  return pd.count > set_count() || (pd.count == set_count() && pd.report_ns >= applied_changed_ns_);
}

void Replicator::handle_gossip(const PeerId& from, Peer& p, const SummaryMsg& m) {
  const bool was_new = !p.announced || p.status == Liveness::kDead;
  if (m.beat == Beat::kFull) {
    if (!take_peer_set(from, p, to_context(m.applied))) return;
    d(p).full = true;
    d(p).full_hash = m.set_hash;
  }
  // Its life: a higher one is news (it refuted a suspicion); a gone peer that talks with the life
  // it was declared gone under is told so, and comes back when it refutes.
  const std::uint32_t life = PeerRecord::clamp_life(m.life);
  if (life > p.life || (life == p.life && p.status != Liveness::kDead)) {
    const bool back = life > p.life && p.status != Liveness::kAlive;
    p.life = life;
    if (back || p.status == Liveness::kSuspect) {
      p.status = Liveness::kAlive;
      p.my_suspicion = false;
      if (back) spread(Rumor{from, p.life, Liveness::kAlive});
    }
    if (!p.alive) {
      p.alive = true;
      if (membership_cb_ && p.announced) membership_cb_(Membership::kJoined, info_of(p));
    }
  } else if (p.status == Liveness::kDead && (seen(p).told_dead_ns < 0 || now_ - seen(p).told_dead_ns >= opt_.probe_ns)) {
    d(p).told_dead_ns = now_;
    send_beat(Beat::kAck, from);  // carries the rumor of its death first
  }
  // A beat without a name (the sender knows we know it) leaves the name we have.
  // A kBehind beat's name field names the replicas behind the gateway, not the gateway.
  const std::string& own_name = m.beat == Beat::kBehind ? kNoName : m.name;
  const bool first = !p.announced && (!own_name.empty() || m.beat == Beat::kHello);
  if (!own_name.empty()) {
    d(p).name = own_name;
    p.named = true;
  }
  p.observer = m.observer;
  // A gateway's acknowledgements count only from its hold answers, and only under its latest
  // generation: replicas that came behind it since have acknowledged nothing (docs/teams.md).
  // A generation that looks older (modulo 64, a newer one is 1 to 31 ahead) is a beat that
  // overtook a newer one, unless the gateway came back or a probe period passed since the last
  // one: then it restarted from its store (same incarnation) and counts from 0 again. Its answers
  // under the generation it left count no more (held()); one that came back is asked afresh.
  const unsigned ahead = static_cast<unsigned>(m.generation - seen(p).behind_generation) & 63u;
  if (m.gateway && seen(p).gateway && ahead == 0) {
    d(p).generation_ns = now_;
  } else if (m.gateway && (!seen(p).gateway || was_new || newer_from_gateway(ahead < 32, seen(p).generation_ns))) {
    if (was_new || ahead >= 32) d(p).holds.clear();
    if (was_new) d(p).behind_version_ns = -1;  // and its list of the replicas behind it, whatever its version
    d(p).behind_generation = m.generation;
    d(p).generation_ns = now_;
    ask_again();
  }
  d(p).gateway = m.gateway;
  remember_name(from, own_name);
  if (first) {
    p.announced = true;
    if (membership_cb_ && p.alive) membership_cb_(Membership::kJoined, info_of(p));
  }
  // A gateway tells a peer new or back at once who is behind it, not at the next refresh.
  if (opt_.gateway && was_new && !opt_.observer) tell_behind(from);
  if (m.set_hash != 0) {
    PeerDetail& pd = d(p);
    pd.differing = m.set_hash == set_hash() ? 0 : static_cast<std::uint8_t>(std::min(pd.differing + 1, 255));
    pd.hash = m.set_hash;
    pd.count = m.count;
    pd.report_ns = now_;
    // An addressed beat says how many of our own changes it holds (your_seq): the rest of its
    // count are other origins' (0: unknown).
    pd.others = addressed_ ? m.count - std::min(m.count, m.your_seq) : 0;
  }
  p.your_seq = std::max(p.your_seq, m.your_seq);
  if (addressed_ && counts(p) && !p.observer) repair_own(from, p, m.your_seq);
  if (m.covered != 0) d(p).covered = m.covered;
  const std::uint64_t life_before = life_;
  // A gateway's list of the replicas behind it is no membership news of this group.
  if (m.beat != Beat::kBehind)
    for (const Rumor& r : m.rumors) hear_rumor(r);
  // Told it is suspected or gone: the refutation goes back to the teller at once, not with the
  // next probe (after a partition heals, each side would otherwise wait a probe turn per step).
  if (life_ > life_before) send_beat(Beat::kAck, from);

  switch (m.beat) {
    case Beat::kHello:
      // A replica new to us (a newcomer, one back, or one that started with us and whose hello
      // we got but which may have missed ours) learns of us from our answer, named.
      // With hello_answers, each member answers with that many chances in (live peers): the
      // transport introduces the others.
      // A hello addressed to this replica always gets its answer.
      if (started_ && (addressed_ || (was_new && (hello_answers() <= 0 ||
                                                  rng_.below(live_peer_count() + 1) <
                                                      static_cast<std::uint64_t>(hello_answers()))))) {
        SummaryMsg a = beat(Beat::kAck, from);
        a.name = opt_.name;
        queue(from, std::move(a));
      }
      break;
    case Beat::kPing: send_beat(Beat::kAck, from, m.subject); break;
    case Beat::kPingReq: send_beat(Beat::kPing, m.subject, from); break;
    case Beat::kAck:
      if (!m.subject.is_null() && !(m.subject == self_)) {
        send_beat(Beat::kRelayedAck, m.subject, from);  // it answered a probe made for `subject`
      } else if (probe_sent_ns_ >= 0 && probe_target_ == from) {
        probe_sent_ns_ = -1;
      }
      break;
    case Beat::kRelayedAck:
      if (probe_sent_ns_ >= 0 && probe_target_ == m.subject) probe_sent_ns_ = -1;
      break;
    case Beat::kFull: break;
    case Beat::kHoldQuery:
    case Beat::kHolds:
    case Beat::kBehind: handle_team_beat(from, p, m); break;
  }

  if (!behind(p)) {
    d(p).pull_failures = 0;
    mismatched_.erase(from);
    if (pulling_ && pull_target_ == from) {
      pulling_ = false;
      pull_timeouts_in_a_row_ = 0;
    }
  } else if (counts(p) && opt_.sample_ns == 0) {
    // A full set that holds more is pulled at once; a hash that differs after a grace (deltas
    // in flight make sets differ for a moment).
    // An empty replica (a newcomer) has nothing in flight to wait for.
    if (!pulling_ && ((seen(p).full && !applied_.includes(seen(p).applied)) || set_count() == 0)) pull_from(from);
    else mismatched_.try_emplace(from, now_);
  }
  if (counts(p) && m.digest != 0 && seen(p).hash == set_hash() && !seen(p).state_refused && !pulling_ && !state_.active &&
      pending_lo_ == 0) {
    if (m.digest == state_digest()) {
      d(p).digest_mismatches = 0;
    } else if (++d(p).digest_mismatches >= 2) {
      d(p).digest_mismatches = 0;
      ++stats_.divergences;
      equivocation("replica " + who(from) +
                   " holds the same deltas as this one but another state: pulling its whole state");
      pull_from(from, true);
    }
  }
}

// A beat from `to` says it holds our own deltas 1..your_seq only. What we published after that
// more than a grace ago (lost, or sent while a partition cut it off) goes to it again from the
// relay buffer; when the buffer no longer holds the first of them, our whole set does (a kFull
// beat), and it pulls what it lacks. Hashes and counts alone miss such a gap while both replicas
// keep changing: each new change makes the sets differ again for a moment.
void Replicator::repair_own(const PeerId& to, Peer& p, std::uint64_t your_seq) {
  const std::uint64_t published = pending_lo_ != 0 ? pending_lo_ - 1 : seq_;
  if (your_seq >= published || (seen(p).repaired_ns >= 0 && now_ - seen(p).repaired_ns < opt_.pull_first_timeout_ns)) return;
  std::vector<const Buffered*> entries;
  bool covered = false;
  if (auto idx = buffer_index_.find(self_); idx != buffer_index_.end()) {
    auto it = idx->second.upper_bound(your_seq + 1);
    if (it != idx->second.begin()) {
      const Buffered& first = *std::prev(it)->second;
      covered = first.hi > your_seq;
      if (covered) it = std::prev(it);
    }
    for (; covered && it != idx->second.end(); ++it) {
      const Buffered& e = *it->second;
      if (now_ - e.at_ns < opt_.gap_grace_ns) break;  // still in flight, most likely
      entries.push_back(&e);
    }
  }
  if (covered && entries.empty()) return;  // the first missing delta was sent just now
  d(p).repaired_ns = now_;
  // A long history goes as a state (handle(PullMsg)): our whole set, and the peer pulls.
  if (!covered || entries.size() > opt_.max_relayed_answer) return send_full(to);
  for (const Buffered* e : entries) {
    queue(to, DeltaMsg{e->origin, e->lo, e->hi, e->bytes, e->signature});
    ++stats_.deltas_relayed;
  }
}

const PeerId* Replicator::next_probe_target() {
  if (peers_.empty()) return nullptr;
  // Now and then a peer believed gone is probed too: after a partition heals, that is how the
  // two sides find each other again without anyone broadcasting.
  const bool dead_turn = (++probes_ % 4) == 0;
  // A live turn while the digest is due probes the peer whose turn it is to get it.
  if (!dead_turn && digest_due_)
    if (auto it = peers_.find(digest_to_); it != peers_.end() && it->second.alive) return &it->first;
  for (const bool want_dead : {dead_turn, false}) {
    auto it = peers_.upper_bound(probe_cursor_);
    for (std::size_t i = 0; i < peers_.size(); ++i, ++it) {
      if (it == peers_.end()) it = peers_.begin();
      const Peer& p = it->second;
      if (p.said_bye) continue;
      if (want_dead ? p.status == Liveness::kDead : p.alive) {
        probe_cursor_ = it->first;
        return &it->first;
      }
    }
    if (!want_dead) break;
  }
  return nullptr;
}

// The peer the digest goes to this period: the next live one after the last, round-robin.
const PeerId* Replicator::next_digest_target() {
  auto it = peers_.upper_bound(digest_to_);
  for (std::size_t i = 0; i < peers_.size(); ++i, ++it) {
    if (it == peers_.end()) it = peers_.begin();
    const Peer& p = it->second;
    if (p.alive && !p.said_bye && p.status == Liveness::kAlive) {
      digest_to_ = it->first;
      return &it->first;
    }
  }
  return nullptr;
}

void Replicator::probe_tick() {
  if (probe_sent_ns_ >= 0) {
    auto it = peers_.find(probe_target_);
    const std::int64_t waited = now_ - probe_sent_ns_;
    if (it == peers_.end() || !it->second.alive) {
      probe_sent_ns_ = -1;
    } else if (waited >= opt_.probe_ns) {
      probe_sent_ns_ = -1;
      suspect(it->second);
    } else if (!probe_indirect_ && waited >= opt_.probe_ns / 2) {
      // Ask a few others to probe it: one lossy link must not make a live peer look gone.
      probe_indirect_ = true;
      std::vector<PeerId> helpers;
      for (const auto& [id, q] : peers_)
        if (q.alive && !(id == probe_target_) && q.status == Liveness::kAlive) helpers.push_back(id);
      for (int k = 0; k < opt_.indirect_probes && !helpers.empty(); ++k) {
        const std::size_t i = rng_.below(helpers.size());
        ++stats_.probes_indirect;
        send_beat(Beat::kPingReq, helpers[i], probe_target_);
        helpers[i] = helpers.back();
        helpers.pop_back();
      }
    }
  }
  if (now_ < next_probe_ns_) return;
  next_probe_ns_ = now_ + opt_.probe_ns;
  if (probe_sent_ns_ >= 0) return;
  const PeerId* target = next_probe_target();
  if (target == nullptr) return;
  const Peer& p = peers_.find(*target)->second;
  ++stats_.probes;
  if (p.status == Liveness::kDead) {  // a gone peer: a ping tells it so; no suspicion follows
    send_beat(Beat::kPing, *target);
    return;
  }
  probe_target_ = *target;
  probe_sent_ns_ = now_;
  probe_indirect_ = false;
  send_beat(Beat::kPing, *target);
}

void Replicator::gossip_tick() {
  // The scans over every peer run at the heartbeat's pace, not every tick: their deadlines are
  // a probe period or longer.
  const bool sweep = now_ >= next_heartbeat_;
  if (hello_due_ && now_ >= next_hello_ns_) {
    hello_due_ = false;
    next_hello_ns_ = now_ + std::min(opt_.pull_first_timeout_ns << std::min(hellos_++, 6), opt_.rediscover_ns);
    say_hello();
  }
  probe_tick();
  // Suspicions this replica raised and nobody refuted: gone. Until then the suspect is pinged
  // every period with the rumor, so that it can refute even when the gossip is slow to reach it.
  const std::int64_t timeout = suspect_timeout();
  for (auto&& [id, p] : peers_) {
    if (!sweep) break;
    if (!p.my_suspicion || p.status != Liveness::kSuspect) continue;
    if (now_ - seen(p).suspect_since >= timeout) {
      declare_dead(p);
    } else if (seen(p).told_dead_ns < 0 || now_ - seen(p).told_dead_ns >= opt_.probe_ns) {
      d(p).told_dead_ns = now_;
      send_beat(Beat::kPing, id);
    }
  }
  // Sets that differed after the grace: pull from one of them.
  if (!pulling_ && opt_.sample_ns == 0) {
    for (auto it = mismatched_.begin(); it != mismatched_.end();) {
      auto p = peers_.find(it->first);
      if (p == peers_.end() || !counts(p->second) || !behind(p->second)) {
        it = mismatched_.erase(it);
        continue;
      }
      if (now_ - it->second >= opt_.gap_grace_ns && !(it->first == last_failed_target_ && mismatched_.size() > 1)) {
        pull_from(it->first);
        mismatched_.erase(it);
        break;
      }
      ++it;
    }
  }
  pull_if_stale();
  if (!pulling_ && opt_.sample_ns > 0 && now_ >= next_sample_) {
    for (const auto& [id, p] : peers_)
      if (counts(p) && behind(p)) {
        pull_from(id);
        next_sample_ = now_ + opt_.sample_ns;
        break;
      }
  }
  if (!pulling_ && gap_pending_ && now_ - gap_since_ns_ >= opt_.gap_grace_ns) {
    if (peer_alive(gap_peer_)) pull_from(gap_peer_);
    gap_pending_ = false;
  }
  // Acknowledgements a claim waits for: asked of the peers that have not given them.
  if (want_acks_seq_ > 0 && now_ >= next_ack_request_ns_) {
    bool all = true;
    for (const auto& [id, p] : peers_) {
      if (!p.alive || held(p, self_) >= want_acks_seq_) continue;
      all = false;
      // A gateway vouches for the replicas behind it only when asked (replicator_behind.cc).
      if (seen(p).gateway) send_hold(Beat::kHoldQuery, id, self_, want_acks_seq_);
      else send_beat(Beat::kPing, id);
    }
    if (all) want_acks_seq_ = 0;
    next_ack_request_ns_ = now_ + opt_.pull_first_timeout_ns;
  }
  // Offered sets this replica now holds all of: say so, once, and forget them.
  for (auto&& [id, p] : peers_) {
    if (!sweep) break;
    if (!seen(p).full || !applied_.includes(seen(p).applied)) continue;
    if (p.alive) send_beat(Beat::kAck, id);
    peer_ranges_ -= seen(p).applied.range_count();
    d(p).applied = crdt::CausalContext{};
    d(p).full = false;
  }
  behind_tick(sweep);
  if (offering_ && now_ >= next_offer_ns_) {
    next_offer_ns_ = now_ + opt_.pull_timeout_ns;
    send_full(PeerId{});
  }
  // Rediscovery: a replica that restarted in a partition, or two groups that forgot each other,
  // are found again by a hello to everyone now and then: each period one replica in about
  // (live peers + 1) sends one, and a replica alone always does. Members answer only a hello from
  // a replica they did not know.
  if (now_ >= next_rediscover_ns_) {
    next_rediscover_ns_ = now_ + opt_.rediscover_ns;
    if (rng_.below(live_peer_count() + 1) == 0) send_beat(Beat::kHello, PeerId{});
  }
  if (opt_.digest_every_ns > 0 && now_ >= next_digest_) {
    next_digest_ = now_ + opt_.digest_every_ns;
    digest_due_ = next_digest_target() != nullptr;
  }
  // Peers gone for long are forgotten (bounded memory): one not alive at two forgetting sweeps in a
  // row, 60 leases apart (so 60 to 120 leases after it went). A record keeps no time (peer_table.h).
  if (sweep && now_ >= next_forget_ns_) {
    next_forget_ns_ = now_ + 60 * opt_.lease_ns;
    for (auto it = peers_.begin(); it != peers_.end();) {
      Peer& p = it->second;
      if (!p.alive && p.gone_at_sweep) {
        peer_ranges_ -= seen(p).applied.range_count();
        mismatched_.erase(it->first);
        it = peers_.erase(it);
      } else {
        p.gone_at_sweep = !p.alive;
        ++it;
      }
    }
  }
  if (sweep) trim_details();
  if (sweep) {
    trim_buffer_gossip();
    next_heartbeat_ = now_ + opt_.heartbeat_ns;
  }
}

void Replicator::trim_buffer_gossip() {
  // Entries are in the order they were remembered (at_ns never decreases along the buffer), so
  // the first one too young for either rule ends the walk: what follows is younger still. Without
  // this, a burst of commits had the walk cross every buffered delta each heartbeat.
  const std::int64_t youngest_droppable = std::min(opt_.gap_grace_ns, opt_.relay_retain_ns);
  for (auto it = buffer_.begin(); it != buffer_.end();) {
    if (now_ - it->at_ns < youngest_droppable) break;
    bool drop;
    if (it->origin == self_) {
      drop = true;
      for (const auto& [id, p] : peers_)
        if (p.alive && p.your_seq < it->hi) {
          drop = false;
          break;
        }
      drop = drop && now_ - it->at_ns >= opt_.gap_grace_ns;
    } else {
      drop = now_ - it->at_ns >= opt_.relay_retain_ns;
    }
    it = drop ? erase_buffered(it) : std::next(it);
  }
  forget_empty_origins();
}

void Replicator::offer_all() {
  if (!opt_.gossip) return announce();
  offering_ = true;
  next_offer_ns_ = now_;
  gossip_tick();
  send_queued();
}

void Replicator::want_acks(std::uint64_t seq) {
  claims_seq_ = std::max(claims_seq_, seq);
  if (!opt_.gossip || seq <= want_acks_seq_) return;
  want_acks_seq_ = seq;
  next_ack_request_ns_ = now_ + opt_.gap_grace_ns;  // the claim's own delivery usually brings them
}

}  // namespace quiver::agents
