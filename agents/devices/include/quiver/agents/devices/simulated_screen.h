#pragma once
/// @file
/// A screen for tests and the simulator: it records what was shown, and when; no files.

#include <cstdint>
#include <optional>
#include <vector>

#include "quiver/agents/devices/screen.h"
#include "quiver/base/result.h"

namespace quiver::agents::devices {

/// One change of a screen: `content` from `t_ns` on (empty for a clear()).
struct ScreenChange {
  std::int64_t t_ns = 0;
  std::optional<ScreenContent> content;

  bool operator==(const ScreenChange&) const = default;
};

/// Records contents; checks them as every Screen does. Renders no pictures (image() stays
/// empty), so the simulator pays nothing for them. Not thread-safe.
class SimulatedScreen final : public Screen {
 public:
  Status show(const ScreenContent& c, std::int64_t now_ns) override;
  Status clear(std::int64_t now_ns) override;
  const std::optional<ScreenContent>& current() const override { return current_; }

  /// Every change so far, oldest first.
  const std::vector<ScreenChange>& history() const { return history_; }

 private:
  std::optional<ScreenContent> current_;
  std::vector<ScreenChange> history_;
};

}  // namespace quiver::agents::devices
