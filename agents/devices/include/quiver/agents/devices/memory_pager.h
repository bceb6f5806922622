#pragma once
/// @file
/// Pages kept in memory, for tests and the simulator.

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "quiver/agents/devices/pager.h"
#include "quiver/base/result.h"

namespace quiver::agents::devices {

/// Keeps every page; checks messages as every Pager does. Not thread-safe.
class MemoryPager final : public Pager {
 public:
  /// @returns encode_page_line()'s errors.
  Status page(std::string_view message, std::int64_t now_ns) override;
  const std::vector<std::string>& sent() const override { return sent_; }

  /// The lines a FilePager would have written, in order.
  const std::vector<std::string>& lines() const { return lines_; }

 private:
  std::vector<std::string> sent_;
  std::vector<std::string> lines_;
};

}  // namespace quiver::agents::devices
