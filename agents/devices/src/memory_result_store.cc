// Test results in memory, encoded and decoded as a file would hold them.
#include "quiver/agents/devices/memory_result_store.h"

#include <utility>

#include "quiver/agents/devices/test_result_json.h"
#include "test_result_json_internal.h"

namespace quiver::agents::devices {

Status MemoryResultStore::store(const TestResult& r) {
  constexpr const char* kFn = "MemoryResultStore::store()";
  Result<std::string> text = encode_test_result(r, kFn);
  if (!text) return text.error();
  // Read back what a file would hold, so a simulation sees exactly what a clinician would.
  Result<TestResult> back = internal::decode_test_result(*text, "(memory)", kFn);
  if (!back) return back.error();
  last_ = std::move(*back);
  last_json_ = std::move(*text);
  ++stored_count_;
  return Status::Ok();
}

}  // namespace quiver::agents::devices
