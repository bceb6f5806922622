#pragma once
/// @file
/// An action: one turn of the DSR loop (seed 000, Algorithm 2) as a first-class shape. The runtime
/// searches the graph for what calls for the action (find), takes the lock its part of the graph
/// needs, marks it executing with a graph change other agents see (start), processes it for as
/// long as it takes (process, on every tick), and writes the result (finish). While it runs it is
/// cancelled as soon as its precondition no longer holds (holds) or its lock is lost: then
/// cancel() stops what it started (a device, an utterance) and takes the mark back.
///
/// Threading: the engine calls every member on the agent's thread, one at a time, marking each
/// call on its CallbackWatch (a call that blocks is reported as hung). Failures are returned as
/// Status; an exception from an action propagates out of the engine's turn.

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>

#include "quiver/agents/runtime/api/context.h"
#include "quiver/graph/ids.h"
#include "quiver/base/result.h"

namespace quiver::agents::inline runtime {

/// What an action works on: nodes by role ("utterance", "person", ...), and a key that tells two
/// runs of one action apart (an action runs at most once per key at a time, and a key already run
/// is not run again until find() stops returning it).
struct Match {
  std::string key;
  std::map<std::string, graph::NodeId, std::less<>> nodes;

  /// The node of `role`, or the null id.
  /// @returns nodes[role] if present, else NodeId{}.
  graph::NodeId at(std::string_view role) const {
    auto it = nodes.find(role);
    return it == nodes.end() ? graph::NodeId{} : it->second;
  }
};

/// A lock an action needs before it starts: the scope rooted at `root`, at `priority`.
struct LockNeed {
  graph::NodeId root;
  std::int64_t priority = 1;
};

enum class Progress : std::uint8_t {
  kRunning,  ///< not done yet: process() is called again on the next tick
  kDone,     ///< finish() comes next
  kFailed,   ///< cancel() comes next (the reason: "failed")
};

/// Why a running action was cancelled. Only started runs are cancelled: in the engine a refused
/// start() is logged and retried later, so kFailed comes from process().
enum class CancelReason : std::uint8_t {
  kPreconditionGone,  ///< holds() turned false
  kLockLost,          ///< another agent took its scope (preempted, or resolved after a partition)
  kFailed,            ///< process() reported failure, or start() was refused
  kStopping,          ///< the agent is stopping
};
/// @returns "precondition gone", "lock lost", "failed", "stopping" (static strings); "unknown"
///          for another value. Thread-safe.
const char* to_string(CancelReason r);

class Action {
 public:
  /// An action called `name` (in logs, events and hang reports).
  explicit Action(std::string name) : name_(std::move(name)) {}
  virtual ~Action() = default;
  /// @returns the name given to the constructor.
  const std::string& name() const { return name_; }

  /// Search for changes: every match that calls for this action now (cheap: it runs after every
  /// relevant change).
  /// @returns the matches; keys must be distinct (a key already running or done is skipped).
  virtual std::vector<Match> find(AgentContext& ctx) = 0;
  /// While running: does its precondition still hold? False cancels it at once.
  /// Also asked while it waits for its lock (false then drops it without cancel()).
  /// @returns whether `m` still calls for the action.
  virtual bool holds(AgentContext& ctx, const Match& m) = 0;
  /// The lock to hold while it runs, if any (taken before start(), released after).
  /// @returns the lock to take, or nullopt (the default) to start without one.
  virtual std::optional<LockNeed> lock(AgentContext& ctx, const Match& m) { return std::nullopt; }
  /// Mark it executing: a graph change other agents see. An error leaves it not started.
  /// @returns OK once started; an error is logged and the match is tried again after
  ///          EngineOptions::retry_ns (no cancel() follows).
  virtual Status start(AgentContext& ctx, const Match& m) = 0;
  /// Process it: called on every tick until it is done or failed (devices work meanwhile).
  /// @returns kRunning, kDone (finish() next) or kFailed (cancel(kFailed) next). The default
  ///          finishes at once.
  virtual Progress process(AgentContext& ctx, const Match& m) { return Progress::kDone; }
  /// Write the result. An error is logged; the action ends anyway.
  /// @returns OK, or why the result could not be written (logged only).
  virtual Status finish(AgentContext& ctx, const Match& m) = 0;
  /// Stop it and take its mark back (graph changes allowed). Called at most once per run.
  /// Called only for a run whose start() succeeded, and never after its finish().
  virtual void cancel(AgentContext& ctx, const Match& m, CancelReason why) = 0;

 private:
  std::string name_;
};

}  // namespace quiver::agents
