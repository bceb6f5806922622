// Replicator pulls: asking a peer for intervals or its whole state, answering pulls from the
// relay buffer or with a state message, and merging a received state.

#include "quiver/agents/replica/replication/replicator.h"

#include <algorithm>

#include "quiver/graph/codec.h"
#include "quiver/graph/state_parts.h"

namespace quiver::agents::inline replica {

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

void Replicator::pull_if_stale() {
  // Hashes that kept differing while the counts never showed this replica behind: changes keep
  // arriving and a peer holds one we lack (a world seeded before DDS matched us, say) or we hold
  // one it lacks. A pull settles both (the peer learns our set and pulls back what it lacks).
  // Under steady change hashes always differ a little, and a pull carries our whole set (its
  // size grows with the origins): the period grows with the peers, two probe rounds at least,
  // so that these pulls cost each replica the same bytes per second at 4 agents as at 1,000.
  if (pulling_ || opt_.sample_ns != 0 || opt_.stale_pull_ns <= 0 || now_ < next_stale_pull_ns_) return;
  for (const auto& [id, p] : peers_)
    if (counts(p) && seen(p).differing >= kStaleReports) {
      pull_from(id);
      next_stale_pull_ns_ =
          now_ + std::max(opt_.stale_pull_ns, 2 * opt_.probe_ns * static_cast<std::int64_t>(live_peer_count() + 1));
      for (auto&& [other, q] : peers_)
        if (seen(q).differing != 0) d(q).differing = 0;
      break;
    }
}

void Replicator::handle(const PeerId& from, const PullMsg& m) {
  if (opt_.gossip) {
    // The puller's whole set came with it: what it holds that we lack is pulled back, and its
    // pull ends with a fresh report of ours (after the answer).
    crdt::CausalContext theirs = to_context(m.applied);
    Peer& p = peers_[from];
    if (!applied_.includes(theirs) && peer_ranges_ + theirs.range_count() <= opt_.max_peer_ranges) {
      peer_ranges_ = peer_ranges_ - seen(p).applied.range_count() + theirs.range_count();
      d(p).applied = std::move(theirs);
      d(p).full = true;
      d(p).full_hash = 0;
      if (!pulling_ && counts(p)) mismatched_.try_emplace(from, now_ - opt_.gap_grace_ns);
    }
  }
  if (m.whole_state || m.as_state) return answer_with_state(from, m);
  crdt::CausalContext missing = applied_.minus(to_context(m.applied));
  if (missing.empty()) {
    // Nothing to give: a summary tells the puller so, and it moves on.
    if (opt_.gossip) send_beat(Beat::kAck, from);
    else send_summary();
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
  // A long history (a joiner's: 1,754 deltas in the 10k-node benchmark, in sync 180 ms after it
  // started) goes as a state instead, which holds only what is there now (about 100 ms), unless a
  // state went to this peer a moment ago.
  if (covered && entries.size() > opt_.max_relayed_answer && state_answer_allowed(from)) covered = false;
  if (covered) {
    ++stats_.pulls_answered_with_deltas;
    for (const Buffered* e : entries) {
      queue(from, DeltaMsg{e->origin, e->lo, e->hi, e->bytes, e->signature});
      ++stats_.deltas_relayed;
    }
    if (opt_.gossip) send_beat(Beat::kAck, from);
    return;
  }
  answer_with_state(from, m);
}

bool Replicator::state_answer_allowed(const PeerId& from) {
  // A whole state is costly to build: to one peer at most once per first-pull patience (an
  // honest puller waits at least that long before asking again).
  const Peer& p = peers_[from];
  return seen(p).last_state_answer_ns < 0 || now_ - seen(p).last_state_answer_ns >= opt_.pull_first_timeout_ns;
}

void Replicator::answer_with_state(const PeerId& from, const PullMsg& m) {
  if (!state_answer_allowed(from)) {
    ++stats_.state_answers_throttled;
    return;
  }
  Peer& p = peers_[from];
  d(p).last_state_answer_ns = now_;
  ++stats_.pulls_answered_with_state;
  // Encoded from the records a few hundred ops at a time, never held as one decoded state.
  std::vector<std::uint8_t> state;
  graph::encode_state(g_, m.whole_state ? crdt::CausalContext{} : to_context(m.context), state);
  const std::size_t chunk = std::clamp<std::size_t>(opt_.chunk_bytes, 1024, opt_.limits.max_chunk_bytes);
  const std::uint64_t count = std::max<std::uint64_t>(1, (state.size() + chunk - 1) / chunk);
  if (count > opt_.limits.max_chunks) {
    return reject(make_error(ErrorCode::kTooLarge, "pull from " + who(from) + ": this replica's state (" +
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
    return reject(make_error(ErrorCode::kTooLarge, "state from " + who(from) + " exceeds max_state_bytes (" +
                                                       std::to_string(opt_.max_state_bytes) + ")"));
  }
  pull_sent_ns_ = now_;  // progress: the pull is alive
  d(peers_[from]).pull_failures = 0;
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
  // Decoded and joined a few hundred ops at a time (a large state is never held decoded whole),
  // and only once all of it decoded and passed admission.
  bool refused = false;
  const graph::PartSink admit = [&](const graph::GraphDelta& part) {
    Status a = admission_->admit_state(from, part);
    refused = !a.ok();
    return a;
  };
  Status s = graph::merge_state(g_, all, scratch_, admission_ != nullptr ? admit : graph::PartSink{});
  if (!s.ok()) {
    if (!refused) return reject(make_error(s.error().code, "state from " + who(from) + ": " + s.error().message));
    ++stats_.states_refused;
    d(peers_[from]).state_refused = true;
    return reject(make_error(ErrorCode::kPermissionDenied, "state from " + who(from) + " refused: " + s.error().message));
  }
  ++state_version_;
  applied_changed_ns_ = now_;
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
  joined(nullptr);
}

}  // namespace quiver::agents
