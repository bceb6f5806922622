#pragma once
/// @file
/// Pages appended to a file that the clinician's app tails.

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "quiver/agents/devices/pager.h"
#include "quiver/base/result.h"

namespace quiver::agents::devices {

/// Appends one JSON line per page (encode_page_line()) to `path`, creating it if missing. Each
/// line goes out in one write() on a file opened with O_APPEND and is fsynced before page()
/// returns. The file is opened per page, so the app may rotate it. Not thread-safe.
class FilePager final : public Pager {
 public:
  explicit FilePager(std::string path);

  /// @returns encode_page_line()'s errors, or kIo naming the file and the OS error.
  Status page(std::string_view message, std::int64_t now_ns) override;
  const std::vector<std::string>& sent() const override { return sent_; }

  const std::string& path() const { return path_; }

 private:
  std::string path_;
  std::vector<std::string> sent_;
};

}  // namespace quiver::agents::devices
