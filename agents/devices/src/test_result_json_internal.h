#pragma once
// decode_test_result() with the caller's function name in its errors.

#include <string>
#include <string_view>

#include "quiver/agents/devices/result_store.h"
#include "quiver/base/result.h"

namespace quiver::agents::devices::internal {

/// As devices::decode_test_result(), naming `fn` in errors.
Result<TestResult> decode_test_result(std::string_view text, const std::string& source,
                                      const char* fn);

}  // namespace quiver::agents::devices::internal
