// The pager file: one synced JSON line appended per page, for the clinician's app to tail.
#include "quiver/agents/devices/file_pager.h"

#include <utility>

#include "file_io.h"

namespace quiver::agents::devices {

FilePager::FilePager(std::string path) : path_(std::move(path)) {}

Status FilePager::page(std::string_view message, std::int64_t now_ns) {
  constexpr const char* kFn = "FilePager::page()";
  Result<std::string> line = encode_page_line(message, now_ns, kFn);
  if (!line) return line.error();
  if (Status s = internal::append_synced(path_, *line, kFn); !s) return s;
  sent_.emplace_back(message);
  return Status::Ok();
}

}  // namespace quiver::agents::devices
