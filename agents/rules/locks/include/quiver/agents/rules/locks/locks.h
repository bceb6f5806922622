#pragma once
/// @file
/// Per-subgraph priority locks, replicated inside the graph CRDT (no lock server).
///
/// A lock protects a scope: a root node with its RT descendants and the edges incident to them.
/// Its state is a register attribute (`__lock`) on the root, so it replicates and merges like any
/// other value: concurrent claims are all kept and every replica picks the same winner, the
/// greatest (epoch, priority, holder). A claim takes epoch = (greatest epoch seen) + 1.
///
/// Semantics (AP, documented in docs/locks.md):
///  - acquire() writes a claim. It is *held* once it is the winner AND every peer this replica
///    currently hears from has acknowledged the delta that carried it. Hence two replicas that
///    hear each other never both hold one scope: the second cannot be acknowledged by the first
///    without the first seeing a competing claim first.
///  - A higher priority preempts (the old holder is told: Lost). An equal or lower priority is
///    refused while the holder's claim lives.
///  - A claim lives while its holder is heard: its engine's heartbeats are the renewal (they go
///    on while the holder's code blocks, DdsReplica::keep_alive()), so claims are written once.
///    A claim whose holder is not heard (it left, crashed, a partition cut it off) has expired:
///    others may then claim the next epoch.
///  - Taking over from a holder that is not heard: the new claim is held only once this replica
///    also holds every change its live peers hold (Replicator::synced()), so that the old
///    holder's last changes, which some peers received and this one may not have (a sample lost
///    to this reader whose writer died before resending it), are here before the new holder acts
///    on the scope. Without peers there is nothing more to learn.
///  - During a partition each side may hold (availability); after the heal the replicas merge
///    the claims, agree on one winner, and the loser gets Lost.
///  - Writes into a scope locked by someone else are refused locally; the holder's writes carry
///    its epoch as their fence, so a stale holder's concurrent write never wins on a register.

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "quiver/agents/replica/replication/replicator.h"
#include "quiver/graph/graph.h"

namespace quiver::agents::inline rules {

struct LockClaim {
  std::uint64_t epoch = 0;
  std::int64_t priority = 0;
  PeerId holder;
  std::int64_t lease_ns = 0;
  bool free = false;  ///< a release: the scope is unlocked at this epoch
};

enum class LockEventKind : std::uint8_t { kAcquired, kLost, kReleased, kExpired };
const char* to_string(LockEventKind k);

struct LockEvent {
  graph::NodeId root;
  LockEventKind kind;
  LockClaim claim;      ///< the claim concerned (for kLost: the winner that took over)
  std::string reason;   ///< e.g. "preempted by priority 5", "resolved after a partition"
  std::int64_t latency_ns = 0;  ///< kAcquired: from acquire() to held
};

struct LockOptions {
  /// Written into claims (their format keeps it); a claim no longer expires by it but with its
  /// holder's liveness (see above).
  std::int64_t lease_ns = 2'000'000'000;
};

class LockManager {
 public:
  /// `replicator` (may be null: then acknowledgement is not required) tells which peers are
  /// live and what they acknowledged. `now` is the clock (virtual in the simulator).
  LockManager(graph::Graph& g, Replicator* replicator, std::function<std::int64_t()> now, LockOptions options = {});
  ~LockManager();
  LockManager(const LockManager&) = delete;
  LockManager& operator=(const LockManager&) = delete;

  /// Claims the scope rooted at `root`. kRefused if another holder's live claim has an equal or
  /// higher priority; kNotFound if `root` does not exist.
  Status acquire(graph::NodeId root, std::int64_t priority);
  /// Releases a scope this replica claimed (held or pending).
  Status release(graph::NodeId root);
  /// Claims several scopes in one canonical order (by node id), so that agents needing several
  /// scopes never wait on each other in a cycle; all-or-nothing: on any refusal the claims made
  /// are released.
  Status acquire_all(std::vector<graph::NodeId> roots, std::int64_t priority);

  /// Held: the winning claim is ours and acknowledged by every live peer.
  bool holds(graph::NodeId root) const;
  /// Ours and winning, but not yet acknowledged by everyone.
  bool pending(graph::NodeId root) const;
  /// The winning claim, if any live one.
  std::optional<LockClaim> winner(graph::NodeId root) const;
  /// Every locked scope's root with its live winning claim (a viewer's overview; costs the
  /// scopes ever claimed, not the graph).
  std::vector<std::pair<graph::NodeId, LockClaim>> winners() const;
  /// True if `node` lies in a scope locked by another replica (writes to it are refused).
  bool locked_by_other(graph::NodeId node) const;
  /// The fencing epoch this replica's writes to `node` carry (0 outside its scopes).
  std::uint64_t fence(graph::NodeId node) const;

  /// Notices expiry and acknowledgement, fires events. Call periodically.
  void tick();
  void on_event(std::function<void(const LockEvent&)> cb) { cb_ = std::move(cb); }

  /// The commit check: refuses a transaction that touches a scope locked by someone else.
  /// Transactions that touch no locked scope pay one hash lookup per node touched.
  Status check(const graph::Graph& g, const std::vector<graph::TxnOp>& ops) const;
  /// Installs check() as the graph's commit validator (chained after `then`, if given) and
  /// fence() as its fence provider.
  void install(graph::Graph::CommitValidator then = {});

 private:
  struct Mine {
    std::uint64_t epoch = 0;
    std::uint64_t seq = 0;  // the delta that carried the claim (for acknowledgement)
    std::int64_t priority = 0;
    std::int64_t requested_at = 0;
    bool held = false;
    bool takeover = false;           // claimed over a holder that was not heard
    mutable bool caught_up = false;  // takeover: this replica held what its peers held, once
  };
  struct Seen {
    LockClaim winner;
    graph::Dot winner_dot;         // the register entry holding it (a renewal changes it)
    std::int64_t changed_at = 0;   // local time the winning entry last changed (for expiry)
    bool expiry_reported = false;
    std::uint64_t max_epoch = 0;  // the greatest epoch among the claims (0 if none)
  };
  void on_changes(const graph::ChangeBatch& b);
  void refresh(graph::NodeId root);
  bool expired(const Seen& s) const;
  bool live(const PeerId& p) const;
  Status write_claim(graph::NodeId root, const LockClaim& c);
  void rebuild_scopes() const;
  void emit(graph::NodeId root, LockEventKind k, const LockClaim& c, std::string reason, std::int64_t latency = 0);

  graph::Graph& g_;
  Replicator* rep_;
  std::function<std::int64_t()> now_;
  LockOptions opt_;
  graph::Graph::SubscriptionId sub_ = 0;
  std::function<void(const LockEvent&)> cb_;
  std::map<graph::NodeId, Seen> seen_;  // every scope with a claim
  std::map<graph::NodeId, Mine> mine_;  // scopes we claimed
  // Materialised scopes, rebuilt lazily when a claim or the RT tree changed.
  mutable std::unordered_map<graph::NodeId, graph::NodeId> foreign_;  // node in others' scope -> root
  mutable std::unordered_map<graph::NodeId, std::uint64_t> own_;      // node -> our epoch
  mutable bool scopes_dirty_ = true;
};

}  // namespace quiver::agents
