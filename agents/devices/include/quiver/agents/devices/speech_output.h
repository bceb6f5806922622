#pragma once
/// @file
/// The text-to-speech device and loudspeaker an agent talks through, behind one interface: a
/// real implementation (EspeakSpeechOutput) and a simulated one (SimulatedSpeechOutput).
///
/// Time is the agent's clock, passed in as `now_ns` (virtual in the simulator); no implementation
/// reads a wall clock. Implementations are not thread-safe: one agent thread owns a device.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "quiver/base/result.h"

namespace quiver::agents::devices {

/// One synthesized utterance and when it plays on the agent's clock.
struct Utterance {
  std::string text;
  std::int64_t start_ns = 0;     ///< when it started playing
  std::int64_t duration_ns = 0;  ///< the length of its audio
  std::string wav_path;          ///< the synthesized audio file; empty for simulated speech

  bool operator==(const Utterance&) const = default;
};

/// Longest text, in bytes, that say() accepts (every implementation: the simulator checks what
/// ships).
inline constexpr std::size_t kMaxUtteranceBytes = 10'000;

/// Checks `text` as every SpeechOutput::say() does.
/// @returns kInvalidArgument naming `fn` when `text` has no visible character (only ASCII
///   whitespace, or nothing) or holds a NUL byte (at the offset given); kTooLarge when it is
///   longer than kMaxUtteranceBytes.
Status check_utterance_text(std::string_view text, const char* fn);

/// Text-to-speech plus a loudspeaker. One utterance plays at a time.
class SpeechOutput {
 public:
  virtual ~SpeechOutput() = default;

  /// Synthesizes `text` and starts playing it at `now_ns` (stopping what played). Its duration
  /// comes from the audio.
  /// @returns the new utterance, or an error: kInvalidArgument when `text` has no visible
  ///   character or holds a NUL byte, kTooLarge when it is longer than kMaxUtteranceBytes, or an
  ///   implementation's synthesis error. After an error the previous utterance is unchanged.
  virtual Result<Utterance> say(std::string_view text, std::int64_t now_ns) = 0;

  /// True while the current utterance plays: now < start + duration, and not stopped.
  /// (False before its start, too.)
  virtual bool playing(std::int64_t now_ns) const = 0;

  /// Stops at once.
  /// @returns how long it had played (ns), 0 if nothing played: 0 without an utterance or when
  ///   it was already stopped, its whole duration when it had ended by itself before `now_ns`.
  virtual std::int64_t stop(std::int64_t now_ns) = 0;

  /// The current (or last) utterance; it stays after it ends or is stopped.
  virtual const std::optional<Utterance>& current() const = 0;
};

}  // namespace quiver::agents::devices
