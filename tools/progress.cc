// The progress line of long runs, drawn on stderr only when stdout is a terminal.
#include "progress.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>

namespace quiver::tools {

ProgressLine::ProgressLine(std::string what, long total)
    : what_(std::move(what)),
      total_(total),
      // QUIVER_PROGRESS=1 draws it anyway (for tests), =0 never.
      shown_(std::getenv("QUIVER_PROGRESS") ? std::getenv("QUIVER_PROGRESS")[0] == '1' : isatty(STDOUT_FILENO) == 1),
      start_(std::chrono::steady_clock::now()),
      last_(start_ - std::chrono::seconds(1)) {}

ProgressLine::~ProgressLine() { finish(); }

void ProgressLine::clear() {
  if (!drawn_) return;
  std::fputs("\r\033[K", stderr);
  std::fflush(stderr);
  drawn_ = false;
  last_ = start_ - std::chrono::seconds(1);
}

void ProgressLine::finish() {
  if (!drawn_) return;
  std::fputc('\n', stderr);
  drawn_ = false;
}

void ProgressLine::update(long done, const std::string& note) {
  if (!shown_) return;
  const auto now = std::chrono::steady_clock::now();
  if (done < total_ && now - last_ < std::chrono::milliseconds(200)) return;
  last_ = now;
  draw(done, note);
}

void ProgressLine::draw(long done, const std::string& note) {
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double pct = total_ > 0 ? 100.0 * static_cast<double>(done) / static_cast<double>(total_) : 100.0;
  char left[48] = "";
  if (done > 0 && done < total_)
    std::snprintf(left, sizeof left, ", about %.0f s left", s / static_cast<double>(done) * static_cast<double>(total_ - done));
  std::fprintf(stderr, "\r%ld/%ld %s (%.0f%%), %.0f s%s%s%s\033[K", done, total_, what_.c_str(), pct, s, left,
               note.empty() ? "" : ", ", note.c_str());
  std::fflush(stderr);
  drawn_ = true;
}

}  // namespace quiver::tools
