#pragma once
/// @file
/// Test results kept in memory, for tests and the simulator.

#include <optional>
#include <string>

#include "quiver/agents/devices/result_store.h"
#include "quiver/base/result.h"

namespace quiver::agents::devices {

/// Keeps the last result. store() encodes it to JSON and decodes it back, as a file would, so
/// that a simulation runs the checks (and the encoding) that ship. Not thread-safe.
class MemoryResultStore final : public ResultStore {
 public:
  /// @returns encode_test_result()'s errors.
  Status store(const TestResult& r) override;
  std::optional<TestResult> last() const override { return last_; }

  /// The JSON text of the last result; empty before the first.
  const std::string& last_json() const { return last_json_; }
  /// How many results were stored.
  int stored_count() const { return stored_count_; }

 private:
  std::optional<TestResult> last_;
  std::string last_json_;
  int stored_count_ = 0;
};

}  // namespace quiver::agents::devices
