// The simulated screen: what was shown, and when, recorded; no pictures.
#include "quiver/agents/devices/simulated_screen.h"

namespace quiver::agents::devices {

Status SimulatedScreen::show(const ScreenContent& c, std::int64_t now_ns) {
  if (Status s = check_screen_content(c, "SimulatedScreen::show()"); !s) return s;
  current_ = c;
  history_.push_back({now_ns, c});
  return Status::Ok();
}

Status SimulatedScreen::clear(std::int64_t now_ns) {
  current_.reset();
  history_.push_back({now_ns, std::nullopt});
  return Status::Ok();
}

}  // namespace quiver::agents::devices
