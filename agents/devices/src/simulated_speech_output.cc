// Simulated speech: no audio, each utterance lasting a fixed time plus a time per word.
#include "quiver/agents/devices/simulated_speech_output.h"

#include <limits>
#include <stdexcept>

namespace quiver::agents::devices {
namespace {

constexpr const char* kSay = "SimulatedSpeechOutput::say()";

bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\v' || c == '\f' || c == '\r';
}

std::int64_t count_words(std::string_view text) {
  std::int64_t words = 0;
  bool in_word = false;
  for (char c : text) {
    if (is_space(c)) {
      in_word = false;
    } else if (!in_word) {
      in_word = true;
      ++words;
    }
  }
  return words;
}

}  // namespace

SimulatedSpeechOutput::SimulatedSpeechOutput(std::int64_t ns_per_word, std::int64_t base_ns)
    : ns_per_word_(ns_per_word), base_ns_(base_ns) {
  if (ns_per_word < 0 || base_ns < 0) {
    throw std::invalid_argument("SimulatedSpeechOutput(): ns_per_word " +
                                std::to_string(ns_per_word) + " and base_ns " +
                                std::to_string(base_ns) + " must not be negative");
  }
}

Result<Utterance> SimulatedSpeechOutput::say(std::string_view text, std::int64_t now_ns) {
  if (Status s = check_utterance_text(text, kSay); !s) return s.error();
  constexpr std::int64_t kMax = std::numeric_limits<std::int64_t>::max();
  const std::int64_t words = count_words(text);
  // Saturates instead of overflowing for absurd rates.
  std::int64_t duration = kMax;
  if (ns_per_word_ == 0 || words <= (kMax - base_ns_) / ns_per_word_) {
    duration = base_ns_ + words * ns_per_word_;
  }
  Utterance u;
  u.text = std::string(text);
  u.start_ns = now_ns;
  u.duration_ns = duration;
  playback_.start(u);
  said_.push_back(u);
  return u;
}

}  // namespace quiver::agents::devices
