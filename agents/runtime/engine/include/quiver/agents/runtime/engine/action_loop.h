#pragma once
/// @file
/// The DSR loop of one agent (seed 000, Algorithm 2), as its engine runs it: change batches are
/// delivered to the agent's subscriptions; each action is searched for again when a change it is
/// interested in arrives (and on every turn); a match takes its lock, is marked executing
/// (start), processed turn after turn, and finished, or cancelled as soon as its precondition no
/// longer holds, its lock is lost, or the agent stops. Every call into the agent's code is marked
/// on the engine's CallbackWatch.
///
/// Threading: the engine's thread only.

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "quiver/agents/runtime/engine/engine.h"

namespace quiver::agents::inline runtime {

class ActionLoop {
 public:
  /// Collects `agent`'s change batches from `engine`'s graph from now on. Engine thread only.
  /// @pre `engine`, `agent` and `stats` outlive the loop.
  ActionLoop(Engine& engine, Agent& agent, Engine::Stats& stats);
  /// Unsubscribes from the graph; runs still in progress are dropped without cancel() (call
  /// stop() first). Engine thread only.
  ~ActionLoop();
  ActionLoop(const ActionLoop&) = delete;
  ActionLoop& operator=(const ActionLoop&) = delete;

  /// Calls the agent's setup() and searches for every action once. @pre locks exist.
  /// @pre Called once; every action is added by the end of setup() (the loop sizes its tables
  ///      then). Engine thread only.
  void start();
  /// Delivers the batches collected since the last call, then re-evaluates the actions.
  /// Does nothing before start(). Engine thread only.
  void pump();
  /// process() of every started run; runs that end are finished or cancelled.
  /// Engine thread only.
  void process();
  /// Marks every action for a new search (time itself may call for one). Engine thread only.
  void dirty_all();
  /// The agent's on_tick(). Engine thread only.
  void on_tick();
  /// Cancels running actions (kStopping), releases their locks, calls teardown().
  /// Does nothing before start(). Engine thread only.
  void stop();
  /// A lock of this agent was lost (LockManager event): its runs end at the next evaluation.
  /// Other kinds of event are ignored. Engine thread only.
  void on_lock_event(const LockEvent& e);

  /// Calls `cb` with every ActionEvent; replaces the previous callback. Engine thread only.
  void on_event(std::function<void(const ActionEvent&)> cb) { event_cb_ = std::move(cb); }
  /// @returns the runs in progress (waiting for a lock or started). Engine thread only.
  std::vector<Engine::RunView> runs() const;
  /// True when no run is in progress. Engine thread only.
  bool idle() const { return runs_.empty(); }

 private:
  struct Run {
    std::size_t action = 0;
    Match match;
    std::optional<LockNeed> lock;
    bool started = false;
  };
  void deliver();
  void evaluate();
  void evaluate_once();
  void start_run(Run& r);
  void end_run(std::size_t index, std::optional<CancelReason> cancelled);
  void emit(ActionEvent::Kind k, const Run& r, CancelReason why = CancelReason::kFailed);
  bool interested(std::size_t action, const graph::ChangeBatch& b) const;
  [[nodiscard]] CallbackWatch::Scope user(const char* callback, std::size_t action);

  Engine& e_;
  Agent& agent_;
  Engine::Stats& stats_;
  graph::Graph::SubscriptionId sub_ = 0;
  std::vector<graph::ChangeBatch> inbox_;   // batches not yet delivered
  std::vector<bool> dirty_;                 // per action: search again
  std::vector<Run> runs_;
  std::set<std::pair<std::size_t, std::string>> done_;  // keys run to completion, still found
  std::map<std::pair<std::size_t, std::string>, std::int64_t> retry_at_;
  std::vector<std::pair<std::size_t, CancelReason>> pending_cancels_;  // run index -> why (lock events)
  std::function<void(const ActionEvent&)> event_cb_;
  bool evaluating_ = false;
  bool started_ = false;
};

}  // namespace quiver::agents::inline runtime
