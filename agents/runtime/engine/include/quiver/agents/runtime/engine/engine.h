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
/// which any thread may call. The replica and the agent belong to the engine's thread.

#include <cstdint>
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
  Engine(graph::Graph& g, Replicator* replicator, EngineOptions options);
  /// The same with `agent` attached (attach()).
  Engine(Agent& agent, graph::Graph& g, Replicator* replicator, EngineOptions options);
  ~Engine() override;
  Engine(const Engine&) = delete;
  Engine& operator=(const Engine&) = delete;

  /// Attaches the agent this engine runs (once, before start()). Its change batches are
  /// collected from now on.
  void attach(Agent& agent);
  /// Loads the grammar (the agent's, or the options'; an error names the file and the place),
  /// installs the grammar and lock checks on the replica and calls the agent's setup().
  /// @returns the grammar's error; the engine then runs no agent code.
  Status start();
  /// Cancels running actions (kStopping), releases their locks, calls teardown().
  void stop();
  /// Installs the grammar and lock checks as the graph's commit validator again, after a host
  /// wrote its set-up without them (Graph::set_commit_validator(nullptr)). @pre started.
  void install_checks();

  // ---- the driver's side ----

  /// Hands a received sample to the replicator (Replicator::on_sample). Call pump() after a
  /// batch of them, so that the agent sees what changed.
  void on_sample(const Sample& s);
  /// Tasks posted from other threads, in order, within the turn budget. A driver calls it every
  /// round, so that call() returns promptly.
  void run_posted();
  /// Due timers, within the turn budget.
  void run_timers();
  /// One round at the engine's tick: the replicator's timers (heartbeats, pulls, liveness), the
  /// agent's turn (tick()), then coalesced deltas leave (Replicator::flush()). Call about every
  /// 10 ms.
  void step();
  /// Delivers the change batches that arrived since the last call to the agent's subscriptions
  /// and searches again for the actions they concern. Call after handing samples over.
  void pump();
  /// The agent's turn: posted tasks and due timers (within the turn budget), lock upkeep, grammar
  /// repairs, process() of running actions, the search for new ones, then on_tick().
  void tick();
  /// The time of the earliest timer (INT64_MAX when none): a driver waits no longer.
  std::int64_t next_timer() const { return timers_.next_due(); }
  /// True when posted tasks wait (a driver should not sleep).
  bool tasks_waiting() const;
  /// Called (from any thread) when a task is posted, so that a waiting driver wakes up.
  void on_posted(std::function<void()> wake) { wake_ = std::move(wake); }

  // ---- other threads ----

  /// Thread-safe: runs `fn` on the engine's thread at its next turn.
  void post(std::function<void()> fn);
  /// Thread-safe: as post(), and returns a future of `fn`'s result (or of its exception). An
  /// engine destroyed before the task ran leaves the future with std::future_error (broken
  /// promise). @pre not waited on from the engine's own thread.
  template <class F>
  auto call(F fn) -> std::future<std::invoke_result_t<F&>> {
    return posted_call([this](std::function<void()> task) { post(std::move(task)); }, std::move(fn));
  }
  /// Where the engine's thread is in user code (for a LivenessKeeper on another thread).
  CallbackWatch& watch() { return watch_; }
  /// Marks a call into user code that the engine does not make itself (e.g. a host's own
  /// callbacks), so that a watcher sees it.
  [[nodiscard]] CallbackWatch::Scope user_code(const char* callback, const std::string* action = nullptr) {
    return watch_.enter(callback, action, now());
  }

  // ---- what the engine holds ----

  Replicator* replicator() { return rep_; }
  /// The lock manager (null for an engine without an agent and without locks_enabled).
  LockManager* lock_manager() { return locks_.get(); }
  /// The grammar guard (null without a grammar).
  GrammarGuard* guard() { return guard_.get(); }
  Agent* agent() { return agent_; }
  bool started() const { return started_; }
  /// Before an action whose start was refused is tried again.
  std::int64_t retry_ns() const { return opt_.retry_ns; }

  void on_action_event(std::function<void(const ActionEvent&)> cb);
  struct Stats {
    std::uint64_t started = 0, finished = 0, cancelled = 0, refused_starts = 0;
    std::uint64_t turns_over_budget = 0;  ///< turns that left tasks or timers for the next round
  };
  const Stats& stats() const;
  /// Runs in progress: (action, key, started).
  struct RunView {
    std::string action, key;
    bool started = false;
  };
  std::vector<RunView> runs() const;

  // ---- AgentContext ----
  const std::string& name() const override;
  graph::Graph& graph() override { return g_; }
  std::int64_t now() const override { return opt_.clock(); }
  LockManager& locks() override;
  Rng& rng() override { return rng_; }
  bool hears(std::string_view agent_name) const override;
  void log(std::string_view line) override;
  TimerId after(std::int64_t delay_ns, std::function<void()> fn) override;
  TimerId every(std::int64_t period_ns, std::function<void()> fn) override;
  void cancel(TimerId id) override { timers_.cancel(id); }
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
