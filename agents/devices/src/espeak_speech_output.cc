// Real text-to-speech with the espeak-ng program: one WAV file per utterance, played on the agent's clock for the
// duration its header gives.
#include "quiver/agents/devices/espeak_speech_output.h"

#include <cstdio>
#include <stdexcept>
#include <utility>
#include <vector>

#include "file_io.h"
#include "quiver/agents/devices/wav_info.h"
#include "run_program.h"

namespace quiver::agents::devices {
namespace {

constexpr const char* kSay = "EspeakSpeechOutput::say()";

// The program's output for an error message: trailing whitespace trimmed, "no output" if none.
std::string describe_output(const std::string& output) {
  std::size_t end = output.find_last_not_of(" \t\r\n");
  if (end == std::string::npos) return "no output";
  return "output: " + output.substr(0, end + 1);
}

}  // namespace

EspeakSpeechOutput::EspeakSpeechOutput(std::string out_dir, std::string voice,
                                       int words_per_minute, std::string program)
    : out_dir_(std::move(out_dir)),
      voice_(std::move(voice)),
      words_per_minute_(words_per_minute),
      program_(std::move(program)) {
  if (out_dir_.empty() || voice_.empty() || program_.empty()) {
    throw std::invalid_argument("EspeakSpeechOutput(): out_dir '" + out_dir_ + "', voice '" +
                                voice_ + "' and program '" + program_ + "' must not be empty");
  }
  if (words_per_minute_ < 1 || words_per_minute_ > 1000) {
    throw std::invalid_argument("EspeakSpeechOutput(): words_per_minute " +
                                std::to_string(words_per_minute_) + " is not in [1, 1000]");
  }
}

Result<Utterance> EspeakSpeechOutput::say(std::string_view text, std::int64_t now_ns) {
  if (Status s = check_utterance_text(text, kSay); !s) return s.error();
  if (Status s = internal::ensure_directory(out_dir_, kSay); !s) return s.error();

  char name[32];
  std::snprintf(name, sizeof name, "utt_%04d.wav", next_index_++);
  std::string wav_path = out_dir_ + "/" + name;

  const std::vector<std::string> argv = {program_, "-v", voice_,
                                         "-s", std::to_string(words_per_minute_),
                                         "-w", wav_path,
                                         "--", std::string(text)};
  Result<internal::ProgramExit> run = internal::run_program(argv, kSay);
  if (!run) return run.error();
  if (!run->exited || run->code != 0) {
    const std::string how = run->exited ? "exited with status " + std::to_string(run->code)
                                        : "was killed by signal " + std::to_string(run->code);
    return make_error(ErrorCode::kIo, std::string(kSay) + ": '" +
                                          internal::quote_command(argv) + "' " + how + " (" +
                                          describe_output(run->output) + ")");
  }

  Result<WavInfo> wav = read_wav_info(wav_path);
  if (!wav) {
    return make_error(wav.error().code, std::string(kSay) + ": after '" +
                                            internal::quote_command(argv) + "': " +
                                            wav.error().message);
  }

  Utterance u;
  u.text = std::string(text);
  u.start_ns = now_ns;
  u.duration_ns = wav->duration_ns;
  u.wav_path = std::move(wav_path);
  playback_.start(u);
  return u;
}

}  // namespace quiver::agents::devices
