#pragma once
/// @file
/// The playback state of a loudspeaker that plays one utterance at a time, modelled by the
/// agent's clock: shared by every SpeechOutput so that real and simulated speech start, end and
/// stop alike.

#include <cstdint>
#include <optional>

#include "quiver/agents/devices/speech_output.h"

namespace quiver::agents::devices {

/// What a loudspeaker plays, on the agent's clock. Not thread-safe.
class Playback {
 public:
  /// Starts `utterance` at its `start_ns`, replacing (stopping) what played.
  /// @pre utterance.duration_ns >= 0.
  void start(Utterance utterance);

  /// True while start <= now < start + duration and stop() was not called since start().
  bool playing(std::int64_t now_ns) const;

  /// Stops the current utterance.
  /// @returns how long it had played: clamp(now - start, 0, duration); 0 without an utterance
  ///   or when it was already stopped.
  std::int64_t stop(std::int64_t now_ns);

  /// The current (or last) utterance.
  const std::optional<Utterance>& current() const { return current_; }

 private:
  std::optional<Utterance> current_;
  bool stopped_ = false;
};

}  // namespace quiver::agents::devices
