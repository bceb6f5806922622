#pragma once
// File writes that survive crashes, for the devices that leave files behind.

#include <string>
#include <string_view>

#include "quiver/base/result.h"

namespace quiver::agents::devices::internal {

/// "No such file or directory" for `err` (an errno value).
std::string errno_text(int err);

/// Writes `bytes` to `<path>.tmp`, fsyncs it, renames it over `path` and fsyncs the directory.
/// On failure `path` is untouched and the temporary file removed.
/// @returns kIo naming `fn`, the file and the OS error.
Status write_file_atomically(const std::string& path, std::string_view bytes, const char* fn);

/// Appends `line` to `path` (created 0644 if missing) in one write() with O_APPEND, then fsyncs.
/// @returns kIo naming `fn`, the file and the OS error.
Status append_synced(const std::string& path, std::string_view line, const char* fn);

/// Creates `dir` and its parents if missing.
/// @returns kIo naming `fn`, the directory and the error.
Status ensure_directory(const std::string& dir, const char* fn);

}  // namespace quiver::agents::devices::internal
