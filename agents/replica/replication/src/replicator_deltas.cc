// Replicator deltas: received deltas recorded, decoded, admitted and applied; equivocations
// (two payloads under one number) flooded and joined; deltas claiming this replica as origin.

#include "quiver/agents/replica/replication/replicator.h"

#include <algorithm>

#include "quiver/base/stage_marks.h"
#include "quiver/graph/codec.h"
#include "replicator_detail.h"

namespace quiver::agents::inline replica {
using internal::digest_of;

Replicator::Buffered* Replicator::recorded(const PeerId& origin, std::uint64_t lo) {
  auto it = buffer_index_.find(origin);
  if (it == buffer_index_.end()) return nullptr;
  auto b = it->second.find(lo);
  return b == it->second.end() ? nullptr : &*b->second;
}

Status Replicator::decode_delta(const PeerId& from, const DeltaMsg& m) {
  // The message names the delta only when there is something to say (the path stays free of
  // allocations when all is well).
  auto what = [&] { return "delta " + delta_of(m.origin, m.lo, m.hi) + " relayed by " + who(from); };
  Status s = graph::decode(*m.payload, scratch_);
  if (!s.ok()) return make_error(s.error().code, what() + ": " + s.error().message);
  if (!(scratch_.origin == m.origin) || scratch_.kind != graph::GraphDelta::Kind::kDelta)
    return make_error(ErrorCode::kMalformed, what() + ": the payload's origin or kind does not match");
  if (scratch_.seq_lo != m.lo || scratch_.seq_hi != m.hi)
    return make_error(ErrorCode::kMalformed, what() + ": the payload names the interval [" +
                                                 std::to_string(scratch_.seq_lo) + ", " +
                                                 std::to_string(scratch_.seq_hi) + "], not the one claimed");
  return {};
}

void Replicator::apply_delta(const PeerId& from, const DeltaMsg& m, std::uint64_t digest) {
  stage_marks::mark(stage_marks::Stage::kMerging);
  g_.merge(scratch_);
  ++state_version_;
  applied_changed_ns_ = now_;
  // A subscriber (a lock manager seeing a claim) asked for an acknowledgement: with gossip it
  // goes to the claim's origin only.
  if (announce_soon_ && opt_.gossip && std::find(ack_to_.begin(), ack_to_.end(), m.origin) == ack_to_.end())
    ack_to_.push_back(m.origin);
  applied_.add_range(m.origin, m.lo, m.hi);
  if (journal_ != nullptr) journal_->remote(m.origin, m.lo, m.hi, *m.payload);
  ++stats_.deltas_applied;
  remember(m.origin, m.lo, m.hi, digest, m.payload, m.signature);
  if (auto it = peers_.find(from); it != peers_.end() && pulling_ && pull_target_ == from) d(it->second).pull_failures = 0;
  if (applied_.contiguous(m.origin) + 1 < m.lo && !gap_pending_) {
    gap_pending_ = true;
    gap_since_ns_ = now_;
    gap_peer_ = from;
  }
  joined(&m);
}

void Replicator::handle(const PeerId& from, const DeltaMsg& m) {
  if (m.origin == self_) return handle_own(from, m);
  const std::uint64_t digest = digest_of(*m.payload);
  if (applied_.includes(m.origin, m.lo, m.hi)) {
    const Buffered* seen = recorded(m.origin, m.lo);
    if (seen == nullptr || seen->knows(m.hi, digest)) {
      ++stats_.deltas_duplicate;
      return;
    }
    return equivocate(from, m, digest, "differs from the one already applied under that interval");
  }
  if (applied_.intersects(m.origin, m.lo, m.hi))
    return equivocate(from, m, digest, "overlaps intervals already applied");
  if (Status s = decode_delta(from, m); !s.ok()) return reject(s.error());
  stage_marks::mark(stage_marks::Stage::kDecoded);
  if (!admitted(from, m, digest)) return;
  stage_marks::mark(stage_marks::Stage::kAdmitted);
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
  ++state_version_;
  remember(m.origin, m.lo, m.hi, digest, m.payload, m.signature);
  queue(PeerId{}, DeltaMsg{m.origin, m.lo, m.hi, m.payload, m.signature});
  reject(s.error());
  joined(&m);
  return false;
}

// The Admission's verdict on the decoded delta in scratch_ (ok without one); a refusal is counted
// and names the delta and its relay.
Status Replicator::admission_verdict(const PeerId& from, const DeltaMsg& m) {
  if (admission_ == nullptr) return {};
  const std::span<const std::uint8_t> sig =
      m.signature ? std::span<const std::uint8_t>(*m.signature) : std::span<const std::uint8_t>();
  const bool authenticated = std::any_of(sender_.begin(), sender_.end(), [](std::uint8_t b) { return b != 0; });
  Status s = admission_->admit_delta(scratch_, *m.payload, sig,
                                     authenticated ? std::span<const std::uint8_t>(sender_) : std::span<const std::uint8_t>());
  if (s.ok()) return s;
  ++stats_.deltas_refused;
  return make_error(ErrorCode::kPermissionDenied, "delta " + delta_of(m.origin, m.lo, m.hi) + " relayed by " +
                                                      who(from) + " refused: " + s.error().message);
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
  equivocation("delta " + delta_of(m.origin, m.lo, m.hi) + " relayed by " + who(from) + " " + what +
               ": both are joined");
  if (Status s = decode_delta(from, m); !s.ok()) return reject(s.error());
  if (Status a = admission_verdict(from, m); !a.ok()) return reject(a.error());
  g_.merge(scratch_);
  ++state_version_;
  applied_.add_range(m.origin, m.lo, m.hi);
  if (journal_ != nullptr) journal_->remote(m.origin, m.lo, m.hi, *m.payload);
  // Remembered by its interval's end and digest, so that its echoes are duplicates: relayed
  // versions that were not would bounce between the replicas for ever.
  Buffered* seen = recorded(m.origin, m.lo);
  bool first_other = false;
  if (seen == nullptr) {
    remember(m.origin, m.lo, m.hi, digest, m.payload, m.signature);
  } else if (seen->others.size() < opt_.max_versions) {
    first_other = seen->others.empty();
    seen->others.push_back(Version{m.hi, digest});
  } else {
    ++stats_.versions_not_relayed;
    return;
  }
  queue(PeerId{}, DeltaMsg{m.origin, m.lo, m.hi, m.payload, m.signature});
  joined(&m);
  if (first_other) queue(PeerId{}, DeltaMsg{m.origin, seen->lo, seen->hi, seen->bytes, seen->signature});
}

// A delta that claims this replica as its origin. An echo of what we published is a duplicate;
// one that differs from it, or one naming numbers we never published, was forged under our name.
void Replicator::handle_own(const PeerId& from, const DeltaMsg& m) {
  const std::uint64_t digest = digest_of(*m.payload);
  if (applied_.includes(self_, m.lo, m.hi)) {
    const Buffered* seen = recorded(self_, m.lo);
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
  equivocation("delta " + delta_of(m.origin, m.lo, m.hi) + " relayed by " + who(from) +
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
  ++state_version_;
  if (journal_ != nullptr) journal_->skipped(seq_ + 1, hi);
  seq_ = hi;
}

}  // namespace quiver::agents
