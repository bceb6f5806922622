#pragma once
/// @file
/// Deterministic speech for tests and the simulator: no audio, no files.

#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

#include "quiver/agents/devices/playback.h"
#include "quiver/agents/devices/speech_output.h"
#include "quiver/base/result.h"

namespace quiver::agents::devices {

/// An utterance of n words (whitespace-separated) lasts base_ns + n * ns_per_word. Not
/// thread-safe.
class SimulatedSpeechOutput final : public SpeechOutput {
 public:
  /// @pre ns_per_word >= 0 and base_ns >= 0 (else std::invalid_argument: a programming error).
  explicit SimulatedSpeechOutput(std::int64_t ns_per_word = 300'000'000,
                                 std::int64_t base_ns = 400'000'000);

  /// Checks `text` as every SpeechOutput does and starts it at `now_ns`; `wav_path` stays empty.
  Result<Utterance> say(std::string_view text, std::int64_t now_ns) override;
  bool playing(std::int64_t now_ns) const override { return playback_.playing(now_ns); }
  std::int64_t stop(std::int64_t now_ns) override { return playback_.stop(now_ns); }
  const std::optional<Utterance>& current() const override { return playback_.current(); }

  /// Every utterance said so far, oldest first.
  const std::vector<Utterance>& said() const { return said_; }

 private:
  std::int64_t ns_per_word_;
  std::int64_t base_ns_;
  Playback playback_;
  std::vector<Utterance> said_;
};

}  // namespace quiver::agents::devices
