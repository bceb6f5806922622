// The pager in memory: every page checked and kept, with the lines a pager file would hold.
#include "quiver/agents/devices/memory_pager.h"

#include <utility>

namespace quiver::agents::devices {

Status MemoryPager::page(std::string_view message, std::int64_t now_ns) {
  Result<std::string> line = encode_page_line(message, now_ns, "MemoryPager::page()");
  if (!line) return line.error();
  sent_.emplace_back(message);
  lines_.push_back(std::move(*line));
  return Status::Ok();
}

}  // namespace quiver::agents::devices
