#pragma once
/// @file
/// Where a byte is in a text, for messages that point into a file ("world.json:12:5: ...").

#include <cstddef>
#include <string>
#include <string_view>

namespace quiver::inline base {

/// "line:column" of byte `byte` of `text`, both counted from 1 (a byte past the end counts as
/// the end). Thread-safe.
/// @returns e.g. "12:5"; columns count bytes, not characters.
inline std::string line_col(std::string_view text, std::size_t byte) {
  std::size_t line = 1, col = 1;
  for (std::size_t i = 0; i < byte && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      col = 1;
    } else {
      ++col;
    }
  }
  return std::to_string(line) + ":" + std::to_string(col);
}

}  // namespace quiver
