#pragma once
// A progress line for long runs, shown on stderr only when stdout is a terminal (a person is
// watching; a pipe or a file gets the results alone). Redrawn at most 5 times a second.
#include <chrono>
#include <string>

namespace quiver::tools {

class ProgressLine {
 public:
  /// `what` names the units, e.g. "steps" or "schedules".
  ProgressLine(std::string what, long total);
  ~ProgressLine();
  /// `done` of the total are done; `note` is appended (e.g. "2 failed").
  void update(long done, const std::string& note = "");
  /// Erases the line (before printing something else; the next update draws it again).
  void clear();
  /// Ends the line, leaving its last state on the terminal.
  void finish();
  /// Whether lines are drawn at all (stdout is a terminal, or forced for tests).
  bool shown() const { return shown_; }

 private:
  void draw(long done, const std::string& note);
  std::string what_;
  long total_;
  bool shown_;
  bool drawn_ = false;
  std::chrono::steady_clock::time_point start_, last_;
};

}  // namespace quiver::tools
