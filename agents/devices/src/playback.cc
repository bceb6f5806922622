// A loudspeaker's playback on the agent's clock: one utterance at a time, playing until its end or a stop.
#include "quiver/agents/devices/playback.h"

#include <algorithm>
#include <utility>

namespace quiver::agents::devices {
namespace {

// now - start, exact when now >= start (no signed overflow for any two int64 values).
std::uint64_t elapsed(std::int64_t start_ns, std::int64_t now_ns) {
  return static_cast<std::uint64_t>(now_ns) - static_cast<std::uint64_t>(start_ns);
}

}  // namespace

void Playback::start(Utterance utterance) {
  current_ = std::move(utterance);
  stopped_ = false;
}

bool Playback::playing(std::int64_t now_ns) const {
  if (!current_ || stopped_ || now_ns < current_->start_ns) return false;
  return elapsed(current_->start_ns, now_ns) < static_cast<std::uint64_t>(current_->duration_ns);
}

std::int64_t Playback::stop(std::int64_t now_ns) {
  if (!current_ || stopped_) return 0;
  stopped_ = true;
  if (now_ns <= current_->start_ns) return 0;
  std::uint64_t played = std::min(elapsed(current_->start_ns, now_ns),
                                  static_cast<std::uint64_t>(current_->duration_ns));
  return static_cast<std::int64_t>(played);
}

}  // namespace quiver::agents::devices
