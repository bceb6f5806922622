#pragma once
/// @file
/// Keeps an agent alive for its peers while its code blocks. An engine's thread runs the
/// protocol and the agent's callbacks in turn; a callback that blocks (a Python process() that
/// sleeps through an utterance, a planner, a camera) would stop its heartbeats, so that its peers
/// saw it leave and its priority locks lapse. The keeper watches the engine's thread from its own
/// (CallbackWatch): while a callback has been running for longer than a heartbeat period it sends
/// the replica's last heartbeat again, once a period; and a callback running longer than the hang
/// limit is reported once, naming the agent, the action and the callback.
///
/// What does wait for the callback: joining what peers send (it is queued, by DDS, and joined as
/// soon as the callback returns) and this agent's own acknowledgements of it.
///
/// Threading: the keeper's own thread calls `beat` and `warn`; both must be thread-safe.

#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <string>
#include <thread>

#include "quiver/agents/runtime/engine/callback_watch.h"

namespace quiver::agents::inline runtime {

struct KeeperOptions {
  std::int64_t beat_ns = 100'000'000;    ///< the replica's heartbeat period
  std::int64_t hang_ns = 1'000'000'000;  ///< a callback running longer is reported (0: never)
  std::function<std::int64_t()> clock;   ///< the clock the watch is stamped with (required)
};

class LivenessKeeper {
 public:
  /// Starts the keeper's thread. `beat` sends the replica's last heartbeat again; `warn` and
  /// `info` take report lines. `watch` must outlive the keeper.
  /// Any thread. @pre o.clock is set and is the clock the watch is stamped with; `beat` and
  ///      `warn` are set; all three callbacks are thread-safe (they run on the keeper's thread).
  LivenessKeeper(const CallbackWatch& watch, KeeperOptions o, std::function<void()> beat,
                 std::function<void(const std::string&)> warn, std::function<void(const std::string&)> info = {});
  /// Stops and joins the thread (waits for a beat or report in progress).
  /// @pre Not called from the keeper's own callbacks.
  ~LivenessKeeper();
  LivenessKeeper(const LivenessKeeper&) = delete;
  LivenessKeeper& operator=(const LivenessKeeper&) = delete;

  /// Heartbeats sent on the agent's behalf, and callbacks reported as hung, so far.
  /// @returns the number of beats. Thread-safe.
  std::uint64_t beats() const;
  /// @returns the number of hung callbacks reported (each call once). Thread-safe.
  std::uint64_t hangs() const;

 private:
  void loop();
  void check(std::int64_t now);

  const CallbackWatch& watch_;
  KeeperOptions opt_;
  std::function<void()> beat_;
  std::function<void(const std::string&)> warn_, info_;
  mutable std::mutex mu_;
  std::condition_variable cv_;
  bool stop_ = false;           // guarded by mu_
  std::uint64_t beats_ = 0, hangs_ = 0;  // guarded by mu_
  // Keeper thread only:
  std::int64_t last_beat_ = 0;
  std::uint64_t reported_call_ = 0;  // the call reported as hung (0: none pending)
  std::int64_t reported_since_ = 0;
  std::string reported_what_;
  std::thread thread_;
};

/// "action 'say' process()", "a timer", ...: the callback of a snapshot, for reports.
/// @returns the callback, prefixed with its action when it has one. Thread-safe.
std::string describe_callback(const CallbackWatch::Snapshot& s);

}  // namespace quiver::agents::inline runtime
