#pragma once
/// @file
/// Rate-limits log lines by kind: a hostile peer can cause thousands of events a second (bad
/// packets, invented peers joining), and a log that prints each one hides everything else. The
/// first `burst` lines of a kind in a period are emitted; the rest are counted and reported as one
/// line ("N more <kind> ..., the last: ...") when the period ends.
///
/// Threading: not thread-safe; guard it if events come from several threads.

#include <cstdint>
#include <functional>
#include <map>
#include <string>

#include "quiver/base/result.h"

namespace quiver::agents::inline replica {

class ErrorLimiter {
 public:
  /// `emit` receives each line to log, on the thread that calls report() or tick().
  /// A `burst` of 0 holds every line back for the summaries.
  explicit ErrorLimiter(std::function<void(const std::string&)> emit, std::int64_t period_ns = 5'000'000'000,
                        int burst = 1)
      : emit_(std::move(emit)), period_ns_(period_ns), burst_(burst) {}

  /// A line of `kind` at time `now_ns`: emitted now, or counted for the kind's next summary.
  /// Runs tick(now_ns) first. Not thread-safe.
  void report(const std::string& kind, const std::string& line, std::int64_t now_ns);
  /// An error: its kind is its code ("malformed", "equivocation", ...). Not thread-safe.
  void report(const Error& e, std::int64_t now_ns) { report(to_string(e.code), e.to_string(), now_ns); }
  /// Emits the summaries of kinds whose period ended. Call from the agent's timer.
  /// Not thread-safe.
  void tick(std::int64_t now_ns);
  /// Lines seen and suppressed over the whole run.
  /// @returns the number of report() calls so far.
  std::uint64_t seen() const { return seen_; }
  /// @returns the number of lines held back (counted into summaries) so far.
  std::uint64_t suppressed() const { return suppressed_; }

 private:
  struct Kind {
    std::int64_t window_start = 0;
    int emitted = 0;         // in the current window
    std::uint64_t held = 0;  // suppressed in the current window
    std::string last;
  };
  std::function<void(const std::string&)> emit_;
  std::int64_t period_ns_;
  int burst_;
  std::map<std::string, Kind> kinds_;
  std::uint64_t seen_ = 0, suppressed_ = 0;
};

}  // namespace quiver::agents
