#pragma once
/// @file
/// An engine's timers: one-shot and periodic functions due at times of the engine's clock (the
/// monotonic clock in a process, virtual time in the simulator).
///
/// Threading: the engine's thread only.

#include <cstdint>
#include <functional>
#include <map>
#include <queue>
#include <vector>

#include "quiver/agents/runtime/api/context.h"  // TimerId

namespace quiver::agents::inline runtime {

class TimerQueue {
 public:
  /// Runs `fn` once at `due`. @returns its id (never 0, never reused).
  TimerId at(std::int64_t due, std::function<void()> fn);
  /// Runs `fn` at `first`, then every `period_ns` (> 0; smaller is taken as 1). A round that falls
  /// a whole period behind runs it once and starts the period again from then. @returns its id.
  TimerId every(std::int64_t first, std::int64_t period_ns, std::function<void()> fn);
  /// Forgets a timer (nothing if it already ran or never was). A timer may cancel itself.
  /// Engine thread only.
  void cancel(TimerId id);
  /// The earliest due time, or INT64_MAX when none.
  /// @returns that time; it may be a cancelled timer's (a wait then ends early).
  std::int64_t next_due() const;
  /// Runs the timers due at `now`, in due order (ties: creation order), while `more()` says so
  /// (a budget); those left wait for the next call. @returns how many ran.
  /// The first due timer always runs; `more` is asked before each further one (empty: run all).
  /// A function may add or cancel timers; an exception from it propagates and the timer is
  /// lost (a periodic one stays scheduled).
  std::size_t run_due(std::int64_t now, const std::function<bool()>& more = {});
  /// @returns true if no timer is scheduled (cancelled ones do not count).
  bool empty() const { return fns_.empty(); }

 private:
  struct Timer {
    std::int64_t due = 0;
    TimerId id = 0;
    std::int64_t period = 0;  // 0: once
    bool operator>(const Timer& o) const { return due != o.due ? due > o.due : id > o.id; }
  };
  std::priority_queue<Timer, std::vector<Timer>, std::greater<Timer>> heap_;
  std::map<TimerId, std::function<void()>> fns_;
  TimerId next_ = 1;
};

}  // namespace quiver::agents::inline runtime
