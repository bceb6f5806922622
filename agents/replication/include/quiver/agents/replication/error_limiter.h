#pragma once
/// @file
/// Rate-limits reports of rejected input: a hostile peer can send thousands of bad packets a
/// second, and a log that prints each one hides everything else. The first error of each kind
/// (its ErrorCode) is reported at once; the rest of that kind within `period` are counted and
/// reported as one line ("N more ... errors, the last: ...") when the period ends.

#include <cstdint>
#include <functional>
#include <map>
#include <string>

#include "quiver/result.h"

namespace quiver::agents {

class ErrorLimiter {
 public:
  /// `emit` receives each line to log; `period_ns` is the quiet time per kind.
  ErrorLimiter(std::function<void(const std::string&)> emit, std::int64_t period_ns = 5'000'000'000)
      : emit_(std::move(emit)), period_ns_(period_ns) {}

  /// An error at time `now_ns`: reported now, or counted for the next summary of its kind.
  void report(const Error& e, std::int64_t now_ns);
  /// Emits the summaries of kinds whose period ended. Call from the agent's timer.
  void tick(std::int64_t now_ns);
  /// Errors seen, reported and suppressed, over the whole run.
  std::uint64_t seen() const { return seen_; }
  std::uint64_t suppressed() const { return suppressed_; }

 private:
  struct Kind {
    std::int64_t window_start = 0;
    std::uint64_t held = 0;  // suppressed in the current window
    std::string last;
  };
  std::function<void(const std::string&)> emit_;
  std::int64_t period_ns_;
  std::map<ErrorCode, Kind> kinds_;
  std::uint64_t seen_ = 0, suppressed_ = 0;
};

}  // namespace quiver::agents
