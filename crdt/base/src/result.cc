// Expected failures as values: the names of the error codes, and an error as text.
#include "quiver/base/result.h"

namespace quiver::inline base {

const char* to_string(ErrorCode code) {
  switch (code) {
    case ErrorCode::kInvalidArgument: return "invalid_argument";
    case ErrorCode::kNotFound: return "not_found";
    case ErrorCode::kAlreadyExists: return "already_exists";
    case ErrorCode::kMalformed: return "malformed";
    case ErrorCode::kTruncated: return "truncated";
    case ErrorCode::kTooLarge: return "too_large";
    case ErrorCode::kUnsupportedVersion: return "unsupported_version";
    case ErrorCode::kTypeMismatch: return "type_mismatch";
    case ErrorCode::kRefused: return "refused";
    case ErrorCode::kTimeout: return "timeout";
    case ErrorCode::kIo: return "io";
    case ErrorCode::kNotConnected: return "not_connected";
    case ErrorCode::kExtrapolation: return "extrapolation";
    case ErrorCode::kTransport: return "transport";
    case ErrorCode::kEquivocation: return "equivocation";
    case ErrorCode::kInternal: return "internal";
    case ErrorCode::kPermissionDenied: return "permission_denied";
  }
  return "unknown";
}

std::string Error::to_string() const { return std::string(quiver::to_string(code)) + ": " + message; }

}  // namespace quiver
