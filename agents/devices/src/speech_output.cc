// The check every speech output makes of the text it is asked to say.
#include "quiver/agents/devices/speech_output.h"

namespace quiver::agents::devices {

Status check_utterance_text(std::string_view text, const char* fn) {
  if (text.size() > kMaxUtteranceBytes) {
    return make_error(ErrorCode::kTooLarge, std::string(fn) + ": the text is " +
                                                std::to_string(text.size()) +
                                                " bytes, more than " +
                                                std::to_string(kMaxUtteranceBytes));
  }
  if (std::size_t nul = text.find('\0'); nul != std::string_view::npos) {
    return make_error(ErrorCode::kInvalidArgument,
                      std::string(fn) + ": the text holds a NUL byte at offset " +
                          std::to_string(nul));
  }
  if (text.find_first_not_of(" \t\n\v\f\r") == std::string_view::npos) {
    return make_error(ErrorCode::kInvalidArgument,
                      std::string(fn) + ": the text '" + std::string(text) +
                          "' has nothing to say");
  }
  return Status::Ok();
}

}  // namespace quiver::agents::devices
