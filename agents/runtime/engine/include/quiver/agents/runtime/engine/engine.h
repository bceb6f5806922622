#pragma once
/// @file
/// The agent engine: the one loop that runs a replica and, when one is attached, an Agent,
/// whatever hosts them. It owns the timers, the tasks other threads post, the jobs, the priority
/// locks and the grammar guard, implements AgentContext, and drives an attached agent through the
/// DSR loop (ActionLoop). A host is a thin driver of it:
///  - the DDS process host (DdsReplica, run_process) waits on its transport, hands every sample to
///    on_sample() and calls step() every tick_ns; a LivenessKeeper on another thread keeps the
///    agent alive for its peers while a callback blocks (watch());
///  - the Python host is the DDS host with Python callbacks;
///  - the simulator calls the same functions in virtual time, for agents and bare replicas alike.
///
/// One round, step(): the replicator's timers (heartbeats, pulls, liveness), then the agent's turn,
/// tick(): tasks posted from other threads and due timers (both within the turn budget; what is
/// left waits for the next round, so that the protocol runs in between), lock and grammar upkeep,
/// running actions' process(), the search for new ones, on_tick(); then coalesced deltas leave.
///
/// Threading: one thread, the engine's, calls everything but post(), call() and watch().snapshot(),
/// which any thread may call. The replica and the agent belong to the engine's thread (in the
/// simulator: the one thread that drives every engine).
///
/// Errors: start() returns the grammar's; refusals inside the loop (an action's start() or
/// finish()) are logged. The engine throws nothing itself; an exception from agent code
/// propagates out of the driver's call (tick(), pump(), start(), ...), except one from a job's
/// work (logged) or from a call()'s function (stored in its future).

#include <cstdint>
#include <set>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "quiver/agents/replica/replication/replicator.h"
#include "quiver/agents/rules/grammar/grammar_guard.h"
#include "quiver/agents/rules/locks/locks.h"
#include "quiver/agents/runtime/api/agent.h"
#include "quiver/agents/runtime/api/posted_call.h"
#include "quiver/agents/runtime/engine/callback_watch.h"
#include "quiver/agents/runtime/engine/job_runner.h"
#include "quiver/agents/runtime/engine/timer_queue.h"
#include "quiver/base/rng.h"

namespace quiver::agents::inline runtime {

class ActionLoop;

struct EngineOptions {
  std::uint64_t seed = 1;                      ///< the agent's random source
  LockOptions locks;                           ///< its priority locks
  std::int64_t retry_ns = 100'000'000;         ///< before trying again an action whose start failed
  std::function<std::int64_t()> clock;         ///< the host's time (required)
  std::function<void(std::string_view)> log;   ///< the host's log (may be null)
  /// The host's log for what a user must see (a peer's change its grammar does not verify);
  /// null: `log`.
  std::function<void(std::string_view)> warn;
  /// Priority locks without an agent (an agent always has them).
  bool locks_enabled = false;
  /// A grammar without an agent (an agent's own grammar wins): file, or text named `source`.
  std::string grammar_file, grammar_text, grammar_source = "grammar";
  /// Tasks and timers of one turn stop once it has run this long (the rest wait a round).
  std::int64_t turn_budget_ns = 20'000'000;
  JobRunner::Mode jobs = JobRunner::Mode::kThread;  ///< the simulator runs jobs inline
};

/// What happened to an action run, for traces, transcripts and checks.
struct ActionEvent {
  enum class Kind : std::uint8_t { kWaitingLock, kStarted, kFinished, kCancelled } kind;
  std::string action;
  std::string key;
  std::int64_t t_ns = 0;
  CancelReason reason = CancelReason::kFailed;  ///< kCancelled
};

class Engine final : public AgentContext {
 public:
  /// An engine for `g` (with `replicator`, may be null: a lone replica, whose locks then need no
  /// acknowledgement). All must outlive it.
  /// The constructing thread becomes the engine's thread (or hands the engine over before use).
  /// @pre options.clock is set; `replicator`, if any, serves `g`.
  Engine(graph::Graph& g, Replicator* replicator, EngineOptions options);
  /// The same with `agent` attached (attach()). @pre as above; `agent` outlives the engine.
  Engine(Agent& agent, graph::Graph& g, Replicator* replicator, EngineOptions options);
  /// Waits for the job in progress (its done() never runs; queued jobs are dropped), detaches
  /// from the graph and, if started, removes the graph's commit validator. Does not call stop().
  /// Engine thread only; futures of call()s not yet run get std::future_error.
  ~Engine() override;
  Engine(const Engine&) = delete;
  Engine& operator=(const Engine&) = delete;

  /// Attaches the agent this engine runs (once, before start()). Its change batches are
  /// collected from now on. Engine thread only.
  /// @pre No agent is attached yet; `agent` outlives the engine.
  void attach(Agent& agent);
  /// Loads the grammar (the agent's, or the options'; an error names the file and the place),
  /// installs the grammar and lock checks on the replica and calls the agent's setup().
  /// @returns the grammar's error; the engine then runs no agent code.
  ///          (kIo for a grammar file that cannot be read, kMalformed for one that does not
  ///          parse, as load_grammar_file() and parse_grammar() report them.) Engine thread only.
  /// @pre Called once.
  Status start();
  /// Cancels running actions (kStopping), releases their locks, calls teardown().
  /// Does nothing before start() or without an agent. Call it once, at the end: the engine's
  /// turns go on if the driver keeps calling them. Engine thread only.
  void stop();
  /// Installs the grammar and lock checks as the graph's commit validator again, after a host
  /// wrote its set-up without them (Graph::set_commit_validator(nullptr)). @pre started.
  /// Engine thread only.
  void install_checks();

  // ---- the driver's side ----

  /// Hands a received sample to the replicator (Replicator::on_sample). Call pump() after a
  /// batch of them, so that the agent sees what changed. Ignored without a replicator.
  /// Engine thread only.
  void on_sample(const Sample& s);
  /// Tasks posted from other threads, in order, within the turn budget. A driver calls it every
  /// round, so that call() returns promptly. Agent::post() tasks join them once started.
  /// Engine thread only.
  void run_posted();
  /// Due timers, within the turn budget. An agent's timers wait for start(). Engine thread only.
  void run_timers();
  /// One round at the engine's tick: the replicator's timers (heartbeats, pulls, liveness), the
  /// agent's turn (tick()), then coalesced deltas leave (Replicator::flush()). Call about every
  /// 10 ms. Engine thread only.
  void step();
  /// Delivers the change batches that arrived since the last call to the agent's subscriptions
  /// and searches again for the actions they concern. Call after handing samples over.
  /// Does nothing before start(). Engine thread only.
  void pump();
  /// The agent's turn: posted tasks and due timers (within the turn budget), lock upkeep, grammar
  /// repairs, process() of running actions, the search for new ones, then on_tick().
  /// Before start() an agent's engine runs posted tasks only. Engine thread only.
  void tick();
  /// The time of the earliest timer (INT64_MAX when none): a driver waits no longer.
  /// It may be a cancelled timer's (the wait then ends early). Engine thread only.
  std::int64_t next_timer() const { return timers_.next_due(); }
  /// True when posted tasks wait (a driver should not sleep). Thread-safe. Tasks posted through
  /// Agent::post() are not counted.
  bool tasks_waiting() const;
  /// True when no task is posted and no action run is in progress (waiting for a lock or
  /// started): a host may then tick it less often. Engine thread only.
  bool quiet() const;
  /// Called (from any thread) when a task is posted, so that a waiting driver wakes up.
  /// `wake` must be thread-safe. Engine thread only.
  /// @pre No other thread can post() yet (the callback is read without a lock).
  void on_posted(std::function<void()> wake) { wake_ = std::move(wake); }

  // ---- other threads ----

  /// Thread-safe: runs `fn` on the engine's thread at its next turn.
  /// Tasks run in post order (marked as user code); the on_posted() callback is called. A task
  /// still queued when the engine is destroyed never runs.
  void post(std::function<void()> fn);
  /// Thread-safe: as post(), and returns a future of `fn`'s result (or of its exception). An
  /// engine destroyed before the task ran leaves the future with std::future_error (broken
  /// promise). @pre not waited on from the engine's own thread.
  /// @returns the future of fn()'s result.
  template <class F>
  auto call(F fn) -> std::future<std::invoke_result_t<F&>> {
    return posted_call([this](std::function<void()> task) { post(std::move(task)); }, std::move(fn));
  }
  /// Where the engine's thread is in user code (for a LivenessKeeper on another thread).
  /// @returns the watch: any thread may call its snapshot(), the rest is the engine thread's.
  CallbackWatch& watch() { return watch_; }
  /// Marks a call into user code that the engine does not make itself (e.g. a host's own
  /// callbacks), so that a watcher sees it. Engine thread only.
  /// @returns the scope; user code runs until it is destroyed. @pre `callback` is a static
  ///          string and `action` (may be null) outlives the scope.
  [[nodiscard]] CallbackWatch::Scope user_code(const char* callback, const std::string* action = nullptr) {
    return watch_.enter(callback, action, now());
  }

  // ---- what the engine holds ----

  /// @returns the replicator given at construction (may be null). Engine thread only.
  Replicator* replicator() { return rep_; }
  /// The lock manager (null for an engine without an agent and without locks_enabled).
  /// Engine thread only; locks() creates it on demand.
  LockManager* lock_manager() { return locks_.get(); }
  /// The grammar guard (null without a grammar; made by start()). Engine thread only.
  GrammarGuard* guard() { return guard_.get(); }
  /// @returns the attached agent, or null. Engine thread only.
  Agent* agent() { return agent_; }
  /// @returns true once start() succeeded (stop() does not reset it). Engine thread only.
  bool started() const { return started_; }
  /// Before an action whose start was refused is tried again.
  /// @returns EngineOptions::retry_ns. Engine thread only.
  std::int64_t retry_ns() const { return opt_.retry_ns; }

  /// Calls `cb` with every ActionEvent (waiting for a lock, started, finished, cancelled), on the
  /// engine's thread. Replaces the previous callback. Engine thread only.
  void on_action_event(std::function<void(const ActionEvent&)> cb);
  struct Stats {
    std::uint64_t started = 0, finished = 0, cancelled = 0, refused_starts = 0;
    std::uint64_t turns_over_budget = 0;  ///< turns that left tasks or timers for the next round
  };
  /// @returns the action counters. Engine thread only.
  const Stats& stats() const;
  /// Runs in progress: (action, key, started).
  struct RunView {
    std::string action, key;
    bool started = false;
  };
  /// @returns the runs in progress, in the order they began (empty without an agent).
  ///          Engine thread only.
  std::vector<RunView> runs() const;

  // ---- AgentContext ---- (engine thread only, as AgentContext says)
  /// @returns the agent's name, else the replicator's ReplicatorOptions::name ("" without
  ///          either).
  const std::string& name() const override;
  /// @returns the replica.
  graph::Graph& graph() override { return g_; }
  /// @returns EngineOptions::clock() (safe from any thread if that clock is).
  std::int64_t now() const override { return opt_.clock(); }
  /// @returns the lock manager, created on first use.
  LockManager& locks() override;
  /// @returns the random source seeded with EngineOptions::seed.
  Rng& rng() override { return rng_; }
  /// @returns false without a replicator; else whether a live, believed, non-observer peer
  ///          announced `agent_name`.
  bool hears(std::string_view agent_name) const override;
  /// Passes `line` to EngineOptions::log (dropped when null). Engine thread only.
  void log(std::string_view line) override;
  /// A negative delay runs at the next round. @returns the timer's id.
  TimerId after(std::int64_t delay_ns, std::function<void()> fn) override;
  /// A period below 1 ns is taken as 1. @returns the timer's id.
  TimerId every(std::int64_t period_ns, std::function<void()> fn) override;
  /// Cancels a timer (nothing if it already ran or never was). Engine thread only.
  void cancel(TimerId id) override { timers_.cancel(id); }
  /// As AgentContext::run_job(); `done` is posted back with post() (also after `work` threw,
  /// which is logged). Engine thread only.
  void run_job(std::function<void()> work, std::function<void()> done) override;

 private:
  void make_locks();
  Status load_grammar();
  bool within_budget() const;

  graph::Graph& g_;
  Replicator* rep_;
  EngineOptions opt_;
  Agent* agent_ = nullptr;
  Rng rng_;
  std::string name_;
  CallbackWatch watch_;
  TimerQueue timers_;
  std::unique_ptr<LockManager> locks_;
  std::unique_ptr<GrammarGuard> guard_;
  std::set<std::uint64_t> peers_verified_;  // agents whose changes a grammar of their own verifies
  std::unique_ptr<ActionLoop> loop_;
  std::unique_ptr<JobRunner> jobs_;
  bool started_ = false;
  Stats stats_;
  mutable std::mutex posted_mu_;
  std::vector<std::function<void()>> posted_;  // guarded by posted_mu_
  std::function<void()> wake_;
  std::function<void(const ActionEvent&)> event_cb_;
  std::int64_t turn_start_ = 0;
};

/// The names this engine had before it ran bare replicas too (issue 21).
using AgentRuntime = Engine;
using RuntimeOptions = EngineOptions;

}  // namespace quiver::agents::inline runtime
