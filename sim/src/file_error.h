#pragma once
// The error of a malformed scenario or fault-schedule file: the file, the JSON pointer of what
// is wrong, and what.

#include <string>

#include "quiver/base/result.h"

namespace quiver::sim::internal {

inline Error file_error(const std::string& source, const std::string& pointer, const std::string& what) {
  return Error{ErrorCode::kInvalidArgument, source + ":" + pointer + ": " + what};
}

}  // namespace quiver::sim::internal
