#pragma once
/// @file
/// The engine that runs one Agent, whatever hosts it: it implements AgentContext on top of a
/// replica, runs the grammar guard and the lock manager, delivers filtered change batches to the
/// agent's subscriptions, fires timers, and drives the agent's actions through the DSR loop
/// (find -> lock -> start -> process -> finish, or cancel). A host (the DDS process host, the
/// simulator) owns the replica and the transport, gives the engine a clock, and calls pump()
/// after delivering messages and tick() periodically.
///
/// Threading: one thread (the host's) calls everything.

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <queue>
#include <set>
#include <string>
#include <vector>

#include "quiver/agents/rules/grammar/grammar_guard.h"
#include "quiver/agents/rules/locks/locks.h"
#include "quiver/agents/replica/replication/replicator.h"
#include "quiver/agents/runtime/api/agent.h"

namespace quiver::agents::inline runtime {

struct RuntimeOptions {
  std::uint64_t seed = 1;                       ///< the agent's random source
  LockOptions locks;
  std::int64_t retry_ns = 100'000'000;          ///< before trying again an action whose start failed
  std::function<std::int64_t()> clock;          ///< the host's time (required)
  std::function<void(std::string_view)> log;    ///< the host's log (may be null)
};

/// What happened to an action run, for traces, transcripts and checks.
struct ActionEvent {
  enum class Kind : std::uint8_t { kWaitingLock, kStarted, kFinished, kCancelled } kind;
  std::string action;
  std::string key;
  std::int64_t t_ns = 0;
  CancelReason reason = CancelReason::kFailed;  ///< kCancelled
};

class AgentRuntime final : public AgentContext {
 public:
  /// `replicator` may be null (locks then need no acknowledgement). All must outlive this.
  AgentRuntime(Agent& agent, graph::Graph& g, Replicator* replicator, RuntimeOptions options);
  ~AgentRuntime() override;
  AgentRuntime(const AgentRuntime&) = delete;
  AgentRuntime& operator=(const AgentRuntime&) = delete;

  /// Loads the agent's grammar (an error names the file and the place), installs the grammar and
  /// lock checks on the replica, and calls the agent's setup().
  Status start();
  /// Delivers the change batches that arrived since the last call to subscriptions, and
  /// re-evaluates the actions they concern. Call after handing messages to the replicator.
  void pump();
  /// Timers, lock renewals, grammar repairs, action processing and searching; then the agent's
  /// on_tick(). Call about every 10 ms.
  void tick();
  /// Cancels running actions (kStopping), releases their locks, calls teardown().
  void stop();

  void on_action_event(std::function<void(const ActionEvent&)> cb) { event_cb_ = std::move(cb); }
  /// The grammar guard (null without a grammar).
  GrammarGuard* guard() { return guard_.get(); }

  struct Stats {
    std::uint64_t started = 0, finished = 0, cancelled = 0, refused_starts = 0;
  };
  const Stats& stats() const { return stats_; }
  /// Runs in progress: (action, key, started).
  struct RunView {
    std::string action, key;
    bool started = false;
  };
  std::vector<RunView> runs() const;

  // ---- AgentContext ----
  const std::string& name() const override { return agent_.name(); }
  graph::Graph& graph() override { return g_; }
  std::int64_t now() const override { return opt_.clock(); }
  LockManager& locks() override { return *locks_; }
  Rng& rng() override { return rng_; }
  bool hears(std::string_view agent_name) const override;
  void log(std::string_view line) override;
  TimerId after(std::int64_t delay_ns, std::function<void()> fn) override;
  TimerId every(std::int64_t period_ns, std::function<void()> fn) override;
  void cancel(TimerId id) override;

 private:
  struct Run {
    std::size_t action = 0;
    Match match;
    std::optional<LockNeed> lock;
    bool started = false;
  };
  struct Timer {
    std::int64_t due = 0;
    TimerId id = 0;
    std::int64_t period = 0;  // 0: once
    bool operator>(const Timer& o) const { return due != o.due ? due > o.due : id > o.id; }
  };
  void deliver();
  void evaluate();
  void evaluate_once();
  void start_run(Run& r);
  void end_run(std::size_t index, std::optional<CancelReason> cancelled);
  void on_lock_event(const LockEvent& e);
  void emit(ActionEvent::Kind k, const Run& r, CancelReason why = CancelReason::kFailed);
  bool interested(std::size_t action, const graph::ChangeBatch& b) const;

  Agent& agent_;
  graph::Graph& g_;
  Replicator* rep_;
  RuntimeOptions opt_;
  Rng rng_;
  std::unique_ptr<LockManager> locks_;
  std::unique_ptr<GrammarGuard> guard_;
  graph::Graph::SubscriptionId sub_ = 0;
  bool started_ = false;

  std::vector<graph::ChangeBatch> inbox_;   // batches not yet delivered
  std::vector<bool> dirty_;                 // per action: search again
  std::vector<Run> runs_;
  std::set<std::pair<std::size_t, std::string>> done_;  // keys run to completion, still found
  std::map<std::pair<std::size_t, std::string>, std::int64_t> retry_at_;
  std::vector<std::pair<std::size_t, CancelReason>> pending_cancels_;  // run index -> why (lock events)

  std::priority_queue<Timer, std::vector<Timer>, std::greater<Timer>> timers_;
  std::map<TimerId, std::function<void()>> timer_fns_;
  TimerId next_timer_ = 1;

  std::function<void(const ActionEvent&)> event_cb_;
  Stats stats_;
  bool evaluating_ = false;
};

}  // namespace quiver::agents
