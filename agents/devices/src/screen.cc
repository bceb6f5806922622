// The check every screen makes of what it is asked to show.
#include "quiver/agents/devices/screen.h"

namespace quiver::agents::devices {

Status check_screen_content(const ScreenContent& c, const char* fn) {
  if (c.options.size() > kMaxScreenOptions) {
    return make_error(ErrorCode::kTooLarge, std::string(fn) + ": " +
                                                std::to_string(c.options.size()) +
                                                " options, more than " +
                                                std::to_string(kMaxScreenOptions));
  }
  for (std::size_t i = 0; i < c.options.size(); ++i) {
    if (c.options[i].empty()) {
      return make_error(ErrorCode::kInvalidArgument,
                        std::string(fn) + ": option " + std::to_string(i) + " has no label");
    }
  }
  const int n = static_cast<int>(c.options.size());
  if (c.highlighted < -1 || c.highlighted >= n) {
    return make_error(ErrorCode::kInvalidArgument,
                      std::string(fn) + ": highlighted " + std::to_string(c.highlighted) +
                          " is neither -1 nor an index into " + std::to_string(n) + " options");
  }
  return Status::Ok();
}

}  // namespace quiver::agents::devices
