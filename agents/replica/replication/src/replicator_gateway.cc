// Replicator, what a gateway calls (bridge.h): a delta another replica of the process joined,
// relayed unchanged; the state another replica holds beyond this one, adopted.

#include "quiver/agents/replica/replication/replicator.h"

#include "quiver/graph/codec.h"

namespace quiver::agents::inline replica {

Result<bool> Replicator::relay(const DeltaMsg& m) {
  if (m.origin.is_null() || m.origin == self_ || m.lo == 0 || m.hi < m.lo || !m.payload)
    return make_error(ErrorCode::kInvalidArgument,
                      "relay(): the delta must name another origin, a sequence interval and a payload");
  const bool fresh = !applied_.intersects(m.origin, m.lo, m.hi);
  const std::uint64_t applied_before = stats_.deltas_applied;
  // As if received from ourselves: a gap it reveals is never pulled from us (peer_alive(self_)
  // is false), and the replies it causes go to everyone.
  handle(self_, m);
  // A refusal and an equivocation queue their own relay; a delta joined here goes out now.
  if (stats_.deltas_applied > applied_before) queue(PeerId{}, m);
  send_queued();
  return fresh && applied_.includes(m.origin, m.lo, m.hi);
}

Status Replicator::adopt_state(const graph::GraphDelta& fragment, const crdt::CausalContext& applied) {
  if (applied.minus(applied_).empty() && fragment.empty()) return {};
  if (admission_ != nullptr)
    if (Status a = admission_->admit_state(self_, fragment); !a.ok()) {
      ++stats_.states_refused;
      return make_error(ErrorCode::kPermissionDenied, "adopted state refused: " + a.error().message);
    }
  g_.merge(fragment);
  ++state_version_;
  applied_changed_ns_ = now_;
  applied_.join(applied);
  if (journal_ != nullptr) journal_->state(graph::encode(fragment), applied);
  skip_own_numbers_to(applied_.max_counter(self_));
  ++stats_.states_applied;
  gap_pending_ = false;
  // The peers learn the new set now rather than at the next digest comparison.
  if (opt_.gossip)
    send_full(PeerId{});
  else
    send_summary();
  send_queued();
  return {};
}

}  // namespace quiver::agents
