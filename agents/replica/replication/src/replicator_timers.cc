// Replicator timers: restoring, starting, announcing and leaving, and the periodic tick (pulls
// timed out and peers suspected, leases expired, pulls started, heartbeats, the buffer trimmed).

#include "quiver/agents/replica/replication/replicator.h"

#include <algorithm>

namespace quiver::agents::inline replica {

void Replicator::restore(const crdt::CausalContext& applied) {
  applied_.join(applied);
  ++state_version_;
  seq_ = std::max(seq_, applied_.max_counter(self_));
}

void Replicator::start(std::int64_t now_ns) {
  now_ = now_ns;
  started_ = true;
  started_ns_ = now_ns;
  next_heartbeat_ = now_ns + opt_.heartbeat_ns;
  next_stale_pull_ns_ = now_ns + opt_.stale_pull_ns;
  if (opt_.gossip) {
    rng_ = Rng(mix64(self_.agent) ^ self_.incarnation);
    // Probes start at a point of the period that depends on the replica, so they do not bunch.
    // Hellos to everyone come from one replica at a time, not all at the same instant.
    next_rediscover_ns_ = now_ns + opt_.rediscover_ns +
                          static_cast<std::int64_t>(rng_.below(static_cast<std::uint64_t>(std::max<std::int64_t>(1, opt_.rediscover_ns))));
    next_probe_ns_ = now_ns + static_cast<std::int64_t>(rng_.below(static_cast<std::uint64_t>(std::max<std::int64_t>(1, opt_.probe_ns))));
    say_hello();
  } else {
    send_summary();
  }
  send_queued();
}

void Replicator::announce() {
  if (opt_.gossip) {
    // Only a newcomer (or a replica that hears nobody) says hello again when its transport
    // matches a new peer: members answer a hello from a replica new to them, so the others need
    // not each tell everyone. At most one per pull_first_timeout_ns, the last one not dropped.
    if (now_ - started_ns_ <= 10 * opt_.probe_ns || live_peer_count() == 0) hello_due_ = true;
    return;
  }
  send_summary();
  send_queued();
}

void Replicator::leave() {
  offering_ = false;
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
    if (auto it = peers_.find(pull_target_); it != peers_.end() && it->second.alive) {
      Peer& p = it->second;
      // Only a peer that keeps talking (its heartbeats arrive) yet never answers is suspected.
      const bool talking = now_ - seen(p).heard_ns <= 2 * opt_.heartbeat_ns;
      if (++d(p).pull_failures >= opt_.suspect_after_timeouts && talking && seen(p).suspect_until <= now_) {
        d(p).suspect_until = now_ + opt_.suspect_ns;
        d(p).pull_failures = 0;
        ++stats_.suspects;
        if (error_cb_) error_cb_(make_error(ErrorCode::kRefused, "peer " + p.id.to_string() + " ('" + seen(p).name + "') left " +
                                                   std::to_string(opt_.suspect_after_timeouts) +
                                                   " pulls in a row unanswered while claiming changes this replica "
                                                   "lacks: its summaries are ignored for " +
                                                   std::to_string(opt_.suspect_ns / 1'000'000) + " ms"));
      }
    }
  }
  for (auto it = peers_.begin(); it != peers_.end() && !opt_.gossip;) {
    Peer& p = it->second;
    if (p.alive && now_ - seen(p).heard_ns > opt_.lease_ns) mark_left(p);
    // Forget peers gone for long (bounded memory); a clean goodbye is kept as long, so that
    // its late packets stay ignored.
    if (!p.alive && now_ - seen(p).heard_ns > 10 * opt_.lease_ns) {
      peer_ranges_ -= seen(p).applied.range_count();
      it = peers_.erase(it);
    } else {
      ++it;
    }
  }
  if (state_.active && now_ - state_.started_ns > 4 * opt_.pull_timeout_ns) state_ = Reassembly{};
  if (opt_.gossip) {
    gossip_tick();
    send_queued();
    return;
  }
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
