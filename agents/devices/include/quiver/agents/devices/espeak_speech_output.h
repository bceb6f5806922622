#pragma once
/// @file
/// Real text-to-speech with the `espeak-ng` program; the WAV file it writes is the output.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "quiver/agents/devices/playback.h"
#include "quiver/agents/devices/speech_output.h"
#include "quiver/base/result.h"

namespace quiver::agents::devices {

/// Synthesizes each utterance with espeak-ng into `<out_dir>/utt_NNNN.wav` (NNNN = 0001, 0002, ...
/// one per say() call, failed calls included, so no file is ever overwritten).
///
/// This machine has no sound card: "playing" is modelled by the agent's clock, from `now_ns`
/// for the duration of the audio read from the WAV header. say() blocks until espeak-ng exits
/// (no time limit). Not thread-safe.
class EspeakSpeechOutput final : public SpeechOutput {
 public:
  /// @param out_dir where the WAV files go; created on the first say() if missing.
  /// @param voice espeak-ng's `-v` voice ("en", "es", "en-us", ...).
  /// @param words_per_minute espeak-ng's `-s` speed.
  /// @param program the espeak-ng executable: a name looked up in PATH, or a path.
  /// @pre out_dir, voice and program are not empty and 1 <= words_per_minute <= 1000 (else
  ///   std::invalid_argument: a programming error).
  explicit EspeakSpeechOutput(std::string out_dir, std::string voice = "en",
                              int words_per_minute = 160, std::string program = "espeak-ng");

  /// Runs `<program> -v <voice> -s <wpm> -w <out_dir>/utt_NNNN.wav -- <text>` (posix_spawnp, no
  /// shell), waits for it, reads the WAV header for the duration and starts playing at `now_ns`.
  /// @returns the utterance, or an error: those of SpeechOutput::say(); kIo when `out_dir` cannot
  ///   be created or the program cannot be started; kNotFound when the program does not exist;
  ///   kIo when it exits with a non-zero status or dies by a signal (the message quotes the
  ///   command and its output); read_wav_info()'s errors for a bad WAV (naming the file).
  Result<Utterance> say(std::string_view text, std::int64_t now_ns) override;
  bool playing(std::int64_t now_ns) const override { return playback_.playing(now_ns); }
  std::int64_t stop(std::int64_t now_ns) override { return playback_.stop(now_ns); }
  const std::optional<Utterance>& current() const override { return playback_.current(); }

  const std::string& out_dir() const { return out_dir_; }

 private:
  std::string out_dir_;
  std::string voice_;
  int words_per_minute_;
  std::string program_;
  int next_index_ = 1;
  Playback playback_;
};

}  // namespace quiver::agents::devices
