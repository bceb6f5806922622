#pragma once
/// @file
/// The Panel agent (seed 000): shows on the touchscreen what the Planner's newest prompt puts on
/// the screen while the patient is there (`panel -[showing]-> u`), clears it when the person is
/// lost, and writes the option the patient touches as `panel -[tapped]-> u`. Grammar:
/// grammars/panel.aggl.
///
/// The picture the screen shows (devices::Screen::image()) goes onto the panel node as the image
/// `screen` (agents/view/images: `screen`, `screen_width`, `screen_height`, `screen_encoding`), in the
/// same transaction as the `showing` mark; a clear replaces it with the blank picture the screen
/// then shows; a (re)started Panel removes a picture an earlier incarnation left. A screen that
/// renders no pictures (SimulatedScreen) stores none.
#include <cstdint>
#include <memory>

#include "quiver/agents/apps/barthel/inputs.h"
#include "quiver/agents/devices/screen.h"
#include "quiver/agents/runtime/api/agent.h"

namespace quiver::agents::inline apps::barthel {

struct PanelOptions {
  std::int64_t presence_stale_ns = 250'000'000;
  std::int64_t touch_period_ns = 20'000'000;
  std::int64_t lock_priority = 1;  ///< on the panel
};

class Panel final : public Agent {
 public:
  Panel(std::unique_ptr<devices::Screen> screen, std::unique_ptr<TouchInput> touch, PanelOptions o = {},
        std::string name = "panel");
  ~Panel() override;
  void setup(AgentContext& ctx) override;
  void status(nlohmann::json& out) const override;
  devices::Screen& screen() { return *screen_; }

 private:
  class Display;
  void poll_touch(AgentContext& ctx);
  void store_screen_image(AgentContext& ctx, graph::Transaction& tx, graph::NodeId panel);
  std::unique_ptr<devices::Screen> screen_;
  std::unique_ptr<TouchInput> touch_;
  PanelOptions opt_;
  std::int64_t handled_touch_ = 0;
  std::uint64_t shown_ = 0, cleared_ = 0, taps_ = 0, images_ = 0;
};

}  // namespace quiver::agents::inline apps::barthel
