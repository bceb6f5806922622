#pragma once
/// @file
/// Where the result of a Barthel test goes for a clinician to validate, behind one interface: a
/// JSON file (JsonResultStore) or memory (MemoryResultStore).

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "quiver/base/result.h"

namespace quiver::agents::devices {

/// The answer to one Barthel item.
struct ItemResult {
  std::string item;          ///< the item's id (BarthelItem::id)
  std::optional<int> score;  ///< empty when the item got no valid answer
  std::string answer;        ///< what the patient said or touched
  std::string channel;       ///< "voice" | "touch" | "" (no answer)

  bool operator==(const ItemResult&) const = default;
};

/// The result of one Barthel test. Strings are UTF-8.
struct TestResult {
  std::string patient;
  std::string status;  ///< "completed" | "clinician_called" | ...
  std::vector<ItemResult> items;
  int total = 0;
  std::int64_t finished_ns = 0;  ///< on the agent's clock

  bool operator==(const TestResult&) const = default;
};

/// A store of test results.
class ResultStore {
 public:
  virtual ~ResultStore() = default;

  /// Stores `r`, replacing the previous result.
  /// @returns kInvalidArgument naming the field when a string is not valid UTF-8 (the JSON
  ///   encoding would be lossy), or the device's error; last() is unchanged after an error.
  virtual Status store(const TestResult& r) = 0;

  /// The result last stored through this store; empty before the first.
  virtual std::optional<TestResult> last() const = 0;
};

}  // namespace quiver::agents::devices
