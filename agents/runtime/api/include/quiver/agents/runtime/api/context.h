#pragma once
/// @file
/// What an agent's code sees of the host it runs in: its replica of the graph, the time (virtual
/// in the simulator), timers, its priority locks, its seeded random source and its log. The same
/// agent class runs unchanged as an OS process over DDS and inside the simulator; only the host
/// behind this interface differs.
///
/// Threading: every member is called on the agent's thread (its host's: the engine's thread),
/// one call at a time (in the simulator, the one thread that drives every agent). Hosts implement
/// it; agents only call it.

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>

#include "quiver/graph/graph.h"
#include "quiver/base/rng.h"

namespace quiver::agents::inline rules {
class LockManager;
}  // namespace quiver::agents::inline rules

namespace quiver::agents::inline runtime {

/// Identifies a timer (to cancel it). 0 is never a timer.
using TimerId = std::uint64_t;

class AgentContext {
 public:
  virtual ~AgentContext() = default;

  /// The agent's name (its replica id derives from it).
  /// @returns a reference valid as long as the host.
  virtual const std::string& name() const = 0;
  /// The agent's replica. Reads and transactions happen on the agent's thread only.
  virtual graph::Graph& graph() = 0;
  /// Now, in nanoseconds: monotonic in a process, virtual in the simulator.
  /// @returns the host's clock; never decreases.
  virtual std::int64_t now() const = 0;
  /// The agent's priority locks (docs/locks.md).
  /// @returns the lock manager, valid as long as the host. Agent's thread only.
  virtual LockManager& locks() = 0;
  /// The one seeded random source of this agent (a seed replays exactly in the simulator).
  /// @returns it; agent's thread only (an Rng is not synchronized).
  virtual Rng& rng() = 0;
  /// True while this agent hears a live agent of that name (its replica's heartbeats arrive, and
  /// it has not lied in its summaries). Without a network (a lone replica): false.
  /// Observers do not count. Agent's thread only.
  virtual bool hears(std::string_view agent_name) const = 0;
  /// A line for the agent's log (named, timed by the host). Agent's thread only.
  virtual void log(std::string_view line) = 0;

  /// Runs `fn` once, `delay_ns` from now. @returns its id.
  /// `fn` runs on the agent's thread; a delay <= 0 means the next turn. Agent's thread only.
  virtual TimerId after(std::int64_t delay_ns, std::function<void()> fn) = 0;
  /// Runs `fn` every `period_ns` (the first time one period from now). @returns its id.
  /// A late turn runs it once, not in a burst. Agent's thread only.
  virtual TimerId every(std::int64_t period_ns, std::function<void()> fn) = 0;
  /// Cancels a timer (nothing if it already ran or never was). A timer may cancel itself.
  /// Agent's thread only.
  virtual void cancel(TimerId id) = 0;

  /// Long work (synthesis, planning, a camera frame) off the agent's thread: `work` runs on a
  /// worker thread and must not touch the graph or this context; then `done` (may be empty) runs
  /// on the agent's thread, where it may. Jobs of one agent run one at a time, in order. A
  /// callback that blocks instead keeps its agent alive for its peers (its heartbeats go on) but
  /// joins nothing until it returns, and is reported as hung past the host's limit.
  /// Agent's thread only (`work` itself runs elsewhere). An exception from `work` is logged and
  /// `done` still runs. The simulator runs `work` at once and `done` at the next turn.
  virtual void run_job(std::function<void()> work, std::function<void()> done) = 0;
};

}  // namespace quiver::agents
