// A page as every pager sends it: one checked JSON line of the time and the message.
#include "quiver/agents/devices/pager.h"

#include <nlohmann/json.hpp>

#include "utf8.h"

namespace quiver::agents::devices {

Result<std::string> encode_page_line(std::string_view message, std::int64_t now_ns,
                                     const char* fn) {
  if (message.empty()) {
    return make_error(ErrorCode::kInvalidArgument, std::string(fn) + ": the message is empty");
  }
  if (message.size() > kMaxPageBytes) {
    return make_error(ErrorCode::kTooLarge, std::string(fn) + ": the message is " +
                                                std::to_string(message.size()) +
                                                " bytes, more than " +
                                                std::to_string(kMaxPageBytes));
  }
  if (auto bad = internal::first_invalid_utf8(message)) {
    return make_error(ErrorCode::kInvalidArgument, std::string(fn) +
                                                       ": the message is not valid UTF-8 (byte " +
                                                       std::to_string(*bad) + ")");
  }
  nlohmann::ordered_json line;
  line["t_ns"] = now_ns;
  line["message"] = std::string(message);
  return line.dump() + "\n";  // compact: one line, newlines inside the message escaped
}

}  // namespace quiver::agents::devices
