#pragma once
/// @file
/// The JSON encoding of a TestResult, shared by every ResultStore (so the memory store checks
/// what the file store writes). The format (pretty-printed, 2-space indent):
///
///     {
///       "patient": "...", "status": "completed",
///       "items": [ {"item": "feeding", "score": 10, "answer": "...", "channel": "voice"}, ... ],
///       "total": 85, "finished_ns": 123, "validated_by_clinician": false
///     }
///
/// `score` is an integer or null. Readers ignore unknown fields.

#include <string>
#include <string_view>

#include "quiver/agents/devices/result_store.h"
#include "quiver/base/result.h"

namespace quiver::agents::devices {

/// Encodes `r` with `"validated_by_clinician": false`.
/// @returns the text (ending in a newline), or kInvalidArgument naming `fn` and the field when
///   a string is not valid UTF-8.
Result<std::string> encode_test_result(const TestResult& r, const char* fn);

/// Decodes a TestResult from `text`; `source` (a file name) and the JSON pointer of the culprit
/// are named in every error.
/// @returns the result, or kMalformed: not JSON (with the byte offset), a missing field, a
///   field of the wrong type, an integer out of range, `validated_by_clinician` not a boolean.
Result<TestResult> decode_test_result(std::string_view text, const std::string& source);

}  // namespace quiver::agents::devices
