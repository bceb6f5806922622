#pragma once
/// @file
/// A replica on DDS: one graph replica, its replicator and the Cyclone DDS transport, driven by
/// the agent engine (engine.h) on one owner thread. This is the engine's DDS driver: it waits on
/// the transport, hands every sample to the engine and calls its round every tick. The owner
/// thread is whichever thread calls spin_*(); every graph read and write, every change event,
/// every protocol step and every agent callback happens there. Other threads talk to it only
/// through post(), call() and stop(), which are thread-safe.
///
/// While the owner thread is inside user code (an agent's callback, a posted task) for longer
/// than a heartbeat, a keeper thread (keep_alive()) sends the replica's last heartbeat again, so
/// that a blocking callback does not make the agent look gone, and reports a callback that does
/// not return.
///
/// Errors: create() returns them as values; nothing here throws (exceptions from user code run
/// on the owner thread propagate out of spin_*()).

#include <atomic>
#include <cstdint>
#include <functional>
#include <future>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>

#include "quiver/agents/replica/replication/replicator.h"
#include "quiver/agents/replica/store/store.h"
#include "quiver/agents/rules/permissions/policy_admission.h"
#include "quiver/agents/rules/schema/schema_admission.h"
#include "quiver/agents/runtime/engine/engine.h"
#include "quiver/agents/runtime/engine/liveness_keeper.h"
#include "quiver/agents/transport/dds/dds_transport.h"
#include "quiver/graph/graph.h"

namespace quiver::agents::inline runtime {

struct DdsReplicaOptions {
  std::string name;                ///< the agent id is derived from it (FNV-1a)
  bool observer = false;           ///< read-only replica (e.g. `quiver dump`)
  std::uint64_t incarnation = 0;   ///< 0: a fresh one (see fresh_incarnation())
  DdsConfig dds;
  ReplicatorOptions replicator;    ///< name and observer are taken from above
  std::int64_t tick_ns = 10'000'000;  ///< the engine's round (replicator timers, the agent's turn)
  /// The round while the replica is quiet: no delta, pull or state received, nothing committed,
  /// no task posted, no action running and no protocol work pending for quiet_after_ns (beats
  /// answered on arrival do not count). An idle agent then wakes 10 times a second instead of
  /// 100 (0: always tick_ns). A replica that hosts no agent, locks or grammar (an observer, a
  /// program that only reads and writes its graph) stays quiet while it receives: it is busy
  /// only while its replicator has work waiting (Replicator::idle()).
  std::int64_t quiet_tick_ns = 100'000'000;
  std::int64_t quiet_after_ns = 500'000'000;
  /// The engine's options (the clock is the monotonic clock; the log is given by the host).
  EngineOptions engine;
  /// A durable store (docs/persistence.md): the replica is loaded from it on start and every
  /// change it joins is logged. A store that cannot be read is set aside (DIR.corrupt-N) and
  /// the replica starts empty under a new incarnation, to be filled by its peers.
  std::optional<StoreOptions> store;
  /// Graph-level permissions and signed deltas (docs/security.md): the replicator's Admission and
  /// the graph's permission check. Null: every well-formed change is joined.
  std::shared_ptr<permissions::PolicyAdmission> permissions;
  /// The shared vocabulary (docs/schema.md): checked on every local commit and on every delta
  /// and state received (after the permissions). Null: none.
  std::shared_ptr<const schema::Schema> schema;
};

/// A new incarnation number for a process start: microseconds of the wall clock shifted left
/// 12 bits, plus 12 random bits. Later starts get larger numbers (so peers replace an old
/// incarnation by a new one), and two starts in the same microsecond still differ.
/// @returns that number (never 0 after 1970). Thread-safe.
std::uint64_t fresh_incarnation();

/// Monotonic time in nanoseconds (the agent's clock).
/// @returns std::chrono::steady_clock's time since its epoch. Thread-safe.
std::int64_t monotonic_ns();

class DdsReplica {
 public:
  /// The longest spin_until() waits before it looks at its predicate again: a quiet replica's
  /// round (the default DdsReplicaOptions::quiet_tick_ns), so that an idle replica waiting in
  /// spin_until() wakes 10 times a second, not 20.
  static constexpr std::int64_t kPredicateLook = 100'000'000;
  /// The longest spin() waits before it looks at stop() again (stop() wakes it at once: the
  /// replica's own ticks, timers and samples decide when it wakes).
  static constexpr std::int64_t kSpinLook = 1'000'000'000;
  /// @returns the replica, or the error of its store, transport or options (naming what failed).
  ///          kInvalidArgument for an empty name; Store::open()'s and DdsTransport::create()'s
  ///          errors as they are (a damaged store is set aside instead: store_recovery()).
  /// Any thread. The replica is started (its first summary is sent) but runs nothing until a
  /// thread calls spin_*(): that thread is then its owner. No agent is attached yet
  /// (engine().attach(), then engine().start()).
  static Result<std::unique_ptr<DdsReplica>> create(DdsReplicaOptions options);
  /// Leaves cleanly: peers see this replica go at once.
  /// Stops the keeper, flushes and says goodbye (Replicator::leave()), disposes its summary
  /// instance. Owner thread only (it does not call the agent's teardown(): Engine::stop() first).
  /// @pre No other thread can still call post(), call() or stop().
  ~DdsReplica();
  DdsReplica(const DdsReplica&) = delete;
  DdsReplica& operator=(const DdsReplica&) = delete;

  /// @returns the replica's graph (for the replica's lifetime). Use it on the owner thread only.
  graph::Graph& graph() { return *graph_; }
  /// @returns the replicator. Use it on the owner thread only, but for last_heartbeat().
  Replicator& replicator() { return *replicator_; }
  /// @returns the transport. Its send() and wake() are thread-safe; the rest belongs to the
  ///          owner thread (which spin_*() already drives).
  DdsTransport& transport() { return *transport_; }
  /// The engine that runs this replica (and the agent attached to it, if any).
  /// @returns it; its post() and call() are thread-safe, the rest is the owner thread's.
  Engine& engine() { return *engine_; }
  /// @returns the options as create() completed them. Any thread (they never change).
  const DdsReplicaOptions& options() const { return opt_; }
  /// The replica's store (null without one). Owner thread only.
  Store* store() { return store_.get(); }
  /// Why the store could not be read on start, if it was set aside (the caller reports it).
  /// Any thread (set by create() only).
  const std::optional<Error>& store_recovery() const { return store_recovery_; }
  /// @returns the replica id: the agent (FNV-1a of the name) and the incarnation in use.
  ///          Any thread (it never changes).
  const PeerId& id() const { return graph_->replica(); }

  /// Owner thread: one round of the loop: waits up to `max_wait_ns` for traffic (less if a timer
  /// is due, none if tasks wait), hands what arrived to the engine, runs posted tasks and due
  /// timers, and the engine's round when its tick is due.
  /// Local commits are published before it waits and at its end. It returns at once on traffic,
  /// a post() or stop(); it does not itself look at stop().
  void spin_once(std::int64_t max_wait_ns);
  /// Owner thread: spins until `done()` holds or `timeout_ns` passes. `done` is checked before the
  /// first round, after every round (each sample, timer or tick ends one) and at least every 100 ms
  /// (kPredicateLook), for a `done` that looks at what other threads change.
  /// @returns whether `done()` held. stop() does not end the wait (check it in `done` if it should).
  bool spin_until(const std::function<bool()>& done, std::int64_t timeout_ns);
  /// Owner thread: spins for `duration_ns` (or until stop()), waking only for samples, timers and
  /// the replica's ticks. Returns at once once stop() was ever called.
  void spin_for(std::int64_t duration_ns);
  /// Owner thread: before leaving cleanly, spins until every live agent peer holds everything
  /// this replica holds (Replicator::peers_hold_all), or `timeout_ns` passes. A peer that was
  /// away may still be pulling what it missed from this replica, perhaps its only holder.
  /// @returns true when handed over.
  bool hand_over(std::int64_t timeout_ns) {
    replicator_->offer_all();
    return spin_until([this] { return replicator_->peers_hold_all(); }, timeout_ns);
  }
  /// Owner thread: spins until stop() is called.
  /// Returns at once if stop() was already called (stop() is not undone).
  void spin();

  /// Owner thread: starts the keeper thread (liveness_keeper.h): while the owner thread is in
  /// user code for longer than a heartbeat, the replica's last heartbeat is sent again once a
  /// heartbeat period; a callback running longer than `hang_ns` (0: never) is reported once
  /// through `warn`, and its return through `info`. Stopped with the replica, or by calling
  /// keep_alive() again.
  /// @pre `warn` is set; `warn` and `info` are thread-safe (they run on the keeper's thread).
  void keep_alive(std::int64_t hang_ns, std::function<void(const std::string&)> warn,
                  std::function<void(const std::string&)> info = {});
  /// Heartbeats the keeper sent on this replica's behalf (0 without a keeper).
  /// @returns that count. Owner thread only (keep_alive() replaces the keeper).
  std::uint64_t kept_beats() const { return keeper_ ? keeper_->beats() : 0; }

  /// Thread-safe: runs `fn` on the owner thread at its next round.
  /// Wakes a round that waits on the transport. A task still queued when the replica is
  /// destroyed never runs.
  void post(std::function<void()> fn) { engine_->post(std::move(fn)); }
  /// Thread-safe: runs `fn` on the owner thread at its next round and returns a future of its
  /// result (or of the exception it threw). A replica destroyed before the task ran leaves the
  /// future with std::future_error (broken_promise).
  /// @pre not called from the owner thread if the caller then waits on the future (it would
  /// wait for itself).
  /// @returns the future of fn()'s result.
  template <class F>
  auto call(F fn) -> std::future<std::invoke_result_t<F&>> {
    return engine_->call(std::move(fn));
  }

  /// Identifies a timer (to cancel it). 0 is never a timer.
  using TimerId = runtime::TimerId;
  /// Owner thread: runs `fn` once on the owner thread, `delay_ns` from now (spin_*() wakes for
  /// it). @returns its id.
  TimerId after(std::int64_t delay_ns, std::function<void()> fn) { return engine_->after(delay_ns, std::move(fn)); }
  /// Owner thread: runs `fn` every `period_ns` (> 0; the first time one period from now).
  /// A round that falls behind runs it once, not once per missed period. @returns its id.
  TimerId every(std::int64_t period_ns, std::function<void()> fn) { return engine_->every(period_ns, std::move(fn)); }
  /// Owner thread: cancels a timer (nothing if it already ran or never was). A timer may cancel
  /// itself from its own function.
  void cancel(TimerId id) { engine_->cancel(id); }
  /// Thread-safe: makes spin() return.
  /// Also spin_for(); for good (a later spin() returns at once). Wakes a waiting round.
  void stop();

 private:
  DdsReplica() = default;
  Result<crdt::CausalContext> open_store(std::uint64_t incarnation);
  DdsReplicaOptions opt_;
  std::unique_ptr<Store> store_;  // outlives the replicator, which logs into it
  std::optional<Error> store_recovery_;
  std::unique_ptr<graph::Graph> graph_;
  std::unique_ptr<DdsTransport> transport_;
  std::unique_ptr<schema::SchemaAdmission> schema_;  // outlives the replicator, whose Admission it is
  std::unique_ptr<Replicator> replicator_;
  std::unique_ptr<Engine> engine_;
  std::unique_ptr<LivenessKeeper> keeper_;  // stopped before the engine and the transport
  std::int64_t next_tick_ = 0;
  std::int64_t last_activity_ns_ = 0;  // the last round that was not quiet (spin_once())
  bool introductions_ = false;        // DDS discovery introduces peers (gossip, unsecured)
  std::uint64_t last_seq_seen_ = 0;    // the replica's own last sequence number then
  std::atomic<bool> stop_{false};
};

/// Opens a replica on the caller's domain with the caller's DDS flags (configuration, security):
/// how a process runner (agents/apps/*/process) gets its observer.
using ReplicaFactory = std::function<Result<std::unique_ptr<DdsReplica>>(DdsReplicaOptions)>;

}  // namespace quiver::agents
