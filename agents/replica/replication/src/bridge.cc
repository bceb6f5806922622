// A bridge between two replicas of one process (a gateway's robot side and team side).

#include "quiver/agents/replica/replication/bridge.h"

#include <algorithm>

namespace quiver::agents::inline replica {

ReplicaBridge::ReplicaBridge(Replicator& a, Replicator& b, std::int64_t check_ns) : r_{&a, &b}, check_ns_(check_ns) {
  for (int i = 0; i < 2; ++i) {
    r_[i]->on_joined([this, i](const DeltaMsg* m) { joined(i, m); });
    // A hold query to one side is answered for the other side's peers too; news of what they
    // hold is passed on at the next pump (outside the replicator that heard it).
    r_[i]->set_behind([this, i](const PeerId& origin, std::uint64_t wanted) {
      return r_[1 - i]->peers_hold_upto(origin, wanted);
    });
    r_[i]->on_holds([this, i](const PeerId& origin) { holds_[1 - i].push_back(origin); });
  }
}

ReplicaBridge::~ReplicaBridge() {
  for (Replicator* r : r_) {
    r->on_joined(nullptr);
    r->set_behind(nullptr);
    r->on_holds(nullptr);
  }
}

void ReplicaBridge::joined(int side, const DeltaMsg* m) {
  if (relaying_into_ == side) return;  // it came from the other side
  if (m == nullptr)
    state_joined_[side] = true;
  else
    out_[side].push_back(*m);
}

bool ReplicaBridge::even() const { return r_[0]->applied() == r_[1]->applied(); }

void ReplicaBridge::adopt(int from, int to) {
  Replicator& src = *r_[from];
  Replicator& dst = *r_[to];
  if (src.applied().minus(dst.applied()).empty()) return;
  relaying_into_ = to;
  // Refused only by dst's Admission, which reports it through its own error callback: the next
  // check tries again.
  if (dst.adopt_state(src.graph().state_diff(dst.graph().context()), src.applied()).ok()) ++stats_.states_to[to];
  relaying_into_ = -1;
}

void ReplicaBridge::pump(std::int64_t now_ns) {
  // Who is alive over there first: a delta relayed below then reaches peers that already know
  // its origin as alive (a claim it carries does not look expired for a moment).
  for (int side = 0; side < 2; ++side) r_[side]->set_members_behind(r_[1 - side]->members_here());
  for (int from = 0; from < 2; ++from) {
    const int to = 1 - from;
    if (out_[from].empty()) continue;
    std::vector<DeltaMsg> batch;
    batch.swap(out_[from]);
    relaying_into_ = to;
    for (const DeltaMsg& m : batch) {
      auto fresh = r_[to]->relay(m);
      if (fresh.ok() && *fresh) ++stats_.deltas_to[to];
    }
    relaying_into_ = -1;
  }
  for (int side = 0; side < 2; ++side) {
    std::vector<PeerId> origins;
    origins.swap(holds_[side]);
    std::sort(origins.begin(), origins.end());
    origins.erase(std::unique(origins.begin(), origins.end()), origins.end());
    for (const PeerId& o : origins) r_[side]->answer_holds(o);
  }
  bool check = now_ns >= next_check_ns_;
  for (int side = 0; side < 2; ++side)
    if (state_joined_[side]) {
      state_joined_[side] = false;
      check = true;
    }
  if (!check) return;
  next_check_ns_ = now_ns + check_ns_;
  if (even()) return;
  adopt(0, 1);
  adopt(1, 0);
}

}  // namespace quiver::agents
