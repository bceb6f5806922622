#pragma once
/// @file
/// The clinician's pager, behind one interface: a file the clinician's app tails (FilePager) or
/// memory (MemoryPager).

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "quiver/base/result.h"

namespace quiver::agents::devices {

/// Longest page message, in bytes (every implementation checks it).
inline constexpr std::size_t kMaxPageBytes = 4096;

/// The line a page is sent as: `{"t_ns":<now_ns>,"message":"<message>"}` and a newline.
/// @returns the line, or an error naming `fn`: kInvalidArgument when `message` is empty or not
///   valid UTF-8, kTooLarge when it is longer than kMaxPageBytes.
Result<std::string> encode_page_line(std::string_view message, std::int64_t now_ns, const char* fn);

/// Calls a clinician.
class Pager {
 public:
  virtual ~Pager() = default;

  /// Sends `message` at `now_ns`.
  /// @returns encode_page_line()'s errors or the device's; nothing is sent then.
  virtual Status page(std::string_view message, std::int64_t now_ns) = 0;

  /// The messages sent so far through this pager, oldest first.
  virtual const std::vector<std::string>& sent() const = 0;
};

}  // namespace quiver::agents::devices
