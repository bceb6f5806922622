#pragma once
/// @file
/// The replicator's peer table: what a replica records of each peer, sized for a thousand of them
/// (docs/protocol.md, "Protocol state per replica").
///
///  - Every peer has a record of 32 bytes: what every member needs (alive, its life and liveness,
///    how many of our own deltas it holds, a few flags).
///  - What a replica records of a peer it deals with (its last report, its offered set, pull and
///    probe bookkeeping, a gateway's generations and holds) is a detail, kept for the peers heard
///    from most recently. With gossip, trim_details() keeps at most a bound of them, never one
///    that holds state a rule waits on (pinned); with all-to-all summaries every peer keeps one.
///
/// Records never move: a reference to one stays valid until that peer is erased, whatever else is
/// added (a detail likewise until trim_details() or its peer's erase). Iterators are invalidated
/// by any insertion or erase, as a vector's.
///
/// Threading: none (the replicator's owner thread).

#include <algorithm>
#include <cstdint>
#include <deque>
#include <limits>
#include <map>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "quiver/agents/replica/replication/messages.h"
#include "quiver/agents/replica/replication/transport.h"
#include "quiver/crdt/causal_context.h"

namespace quiver::agents::inline replica {

/// What every peer has (32 bytes).
struct PeerRecord {
  /// Lives are kept in 32 bits: a life beyond it (only a rogue's) counts as the greatest.
  static constexpr std::uint64_t kMaxLife = std::numeric_limits<std::uint32_t>::max();
  static std::uint32_t clamp_life(std::uint64_t life) {
    return static_cast<std::uint32_t>(life < kMaxLife ? life : kMaxLife);
  }

  PeerId id;
  std::uint64_t your_seq = 0;  // it holds this replica's own 1..your_seq
  std::uint32_t life = 0;      // its life as last heard or rumored (clamp_life())
  Liveness status = Liveness::kAlive;
  bool alive : 1 = false;
  bool observer : 1 = false;
  bool announced : 1 = false;     // kJoined was reported (once its summary named it)
  bool said_bye : 1 = false;      // it left cleanly: late messages of this incarnation are ignored
  bool my_suspicion : 1 = false;  // this replica suspects it (and declares it gone when the time is up)
  bool told_name : 1 = false;     // a beat of ours named us to it
  bool gone_at_sweep : 1 = false;  // gossip: not alive at the last forgetting sweep
  bool named : 1 = false;          // it told its name (its detail, while it has one, keeps it)
};

/// What a replica records of a peer it deals with.
struct PeerDetail {
  std::string name;
  crdt::CausalContext applied;  // its last summary's set (gossip: its last kFull, while `full`)
  std::int64_t heard_ns = 0;    // last heard from (with gossip: while it has a detail)
  std::int64_t used_ns = 0;     // last written to (trim_details() keeps the most recent)
  bool gateway = false;         // one side of a gateway (ReplicatorOptions::gateway)
  bool state_refused = false;   // it sent a state the Admission refused: no digest repair with it
  bool full = false;            // `applied` holds its last kFull (or pull) set, not yet covered here
  std::uint8_t differing = 0;   // its reports in a row whose set hash differed from ours (stale_pull_ns)
  int pull_failures = 0;        // pulls in a row it left unanswered
  int digest_mismatches = 0;    // summaries in a row with our (origin, seq) set but another digest
  std::int64_t suspect_until = 0;
  std::int64_t last_state_answer_ns = -1;
  std::uint64_t full_hash = 0;  // that set's hash, acknowledged (covered) once this replica holds it
  std::int64_t suspect_since = 0;
  std::int64_t told_dead_ns = -1;
  std::uint64_t hash = 0, count = 0;  // its last reported (origin, seq) set: hash and size
  std::uint64_t others = 0;  // of that count, other origins' than ours (from an addressed beat; 0: unknown)
  std::int64_t report_ns = -1;
  std::uint64_t covered = 0;      // the hash of our last offered set it holds all of
  std::int64_t repaired_ns = -1;  // our own deltas it lacked were last sent again then (repair_own())
  // Teams (replicator_behind.cc): how far it (and the replicas behind it) holds other origins.
  struct Held {
    PeerId origin;
    std::uint64_t n = 0;          // it said it holds origin's 1..n (kHolds)
    std::int64_t asked_ns = -1;   // our last hold query about origin
    std::uint8_t generation = 0;  // the gateway's generation when it said so
  };
  std::vector<Held> holds;             // bounded (kMaxHolds), the oldest asked dropped first
  std::uint8_t behind_generation = 0;  // a gateway's latest (SummaryMsg::generation)
  std::uint64_t behind_version = 0;    // a gateway's: the version of its list of replicas behind it last taken
  // When each of those two was last taken (-1: never). A value that looks older is a beat
  // reordered only shortly after; later, it is a gateway that restarted (its counters start
  // again from 0 under the incarnation its store kept) and it is taken: newer_from_gateway().
  std::int64_t generation_ns = -1;
  std::int64_t behind_version_ns = -1;
};

/// Peers by id, ascending: the interface of the std::map it replaced (find, operator[],
/// try_emplace, erase, upper_bound, iteration over (id, record) pairs), records that never move,
/// and the details beside them.
class PeerTable {
 public:
  template <bool Const>
  class Iterator {
   public:
    using Record = std::conditional_t<Const, const PeerRecord, PeerRecord>;
    using value_type = std::pair<const PeerId&, Record&>;
    struct Arrow {
      value_type v;
      const value_type* operator->() const { return &v; }
    };
    Iterator() = default;
    Iterator(std::conditional_t<Const, const PeerTable*, PeerTable*> t, std::size_t i) : t_(t), i_(i) {}
    operator Iterator<true>() const { return Iterator<true>(t_, i_); }
    value_type operator*() const {
      Record& r = t_->slots_[t_->order_[i_]];
      return value_type(r.id, r);
    }
    Arrow operator->() const { return Arrow{**this}; }
    Iterator& operator++() { return ++i_, *this; }
    bool operator==(const Iterator& o) const { return i_ == o.i_; }
    std::size_t index() const { return i_; }

   private:
    std::conditional_t<Const, const PeerTable*, PeerTable*> t_ = nullptr;
    std::size_t i_ = 0;
  };
  using iterator = Iterator<false>;
  using const_iterator = Iterator<true>;

  /// At most 65,535 peers (slots are 16-bit).
  static constexpr std::size_t kMaxPeers = std::numeric_limits<std::uint16_t>::max();

  iterator begin() { return {this, 0}; }
  iterator end() { return {this, order_.size()}; }
  const_iterator begin() const { return {this, 0}; }
  const_iterator end() const { return {this, order_.size()}; }
  std::size_t size() const { return order_.size(); }
  bool empty() const { return order_.empty(); }
  std::size_t count(const PeerId& id) const { return has_at(lower(id), id) ? 1 : 0; }

  iterator find(const PeerId& id) {
    const std::size_t i = lower(id);
    return has_at(i, id) ? iterator{this, i} : end();
  }
  const_iterator find(const PeerId& id) const {
    const std::size_t i = lower(id);
    return has_at(i, id) ? const_iterator{this, i} : end();
  }
  /// The first peer after `id`.
  iterator upper_bound(const PeerId& id);
  /// The peer's record, added (with only its id) when it has none. Beyond kMaxPeers a spare
  /// record stands in, forgotten at the next call: callers keep their own, lower bound
  /// (ReplicatorOptions::max_peers).
  PeerRecord& operator[](const PeerId& id);
  /// Adds the peer (with only its id) when it has no record. @returns its place, and whether it
  /// was added; end() when the table holds kMaxPeers already.
  std::pair<iterator, bool> try_emplace(const PeerId& id);
  /// Erases the peer and its detail. @returns the iterator after it.
  iterator erase(iterator it);

  /// The peer's detail, made when it has none; marks it used at `now_ns`.
  PeerDetail& detail(const PeerRecord& p, std::int64_t now_ns);
  /// The peer's detail when it has one, else one with every field at its default.
  const PeerDetail& seen(const PeerRecord& p) const;
  /// Details, by peer id: iterated, and erased by trim_details().
  const std::map<PeerId, PeerDetail>& details() const { return details_; }
  /// Keeps at most `keep` details: the least recently used of those `pinned` says may go are
  /// erased first; pinned ones stay whatever their number.
  template <class Pinned>
  void trim_details(std::size_t keep, Pinned&& pinned);
  /// Bytes the table holds: records, index, free slots and details (std::map nodes estimated).
  std::size_t memory_bytes() const;

 private:
  /// The place of the first peer not before `id`.
  std::size_t lower(const PeerId& id) const;
  /// True if the peer at place `i` (lower(id)) is `id`.
  bool has_at(std::size_t i, const PeerId& id) const { return i < order_.size() && slots_[order_[i]].id == id; }

  std::deque<PeerRecord> slots_;     // records never move (a deque grows at its end in place)
  std::vector<std::uint16_t> order_;  // slots sorted by id
  std::vector<std::uint16_t> free_;   // slots erased, reused first
  std::map<PeerId, PeerDetail> details_;
  PeerRecord spare_;
};

template <class Pinned>
void PeerTable::trim_details(std::size_t keep, Pinned&& pinned) {
  if (details_.size() <= keep) return;
  std::vector<std::pair<std::int64_t, PeerId>> may_go;
  for (const auto& [id, d] : details_)
    if (!pinned(id, d)) may_go.emplace_back(d.used_ns, id);
  std::sort(may_go.begin(), may_go.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  for (std::size_t i = 0; i < may_go.size() && details_.size() > keep; ++i) details_.erase(may_go[i].second);
}

}  // namespace quiver::agents
