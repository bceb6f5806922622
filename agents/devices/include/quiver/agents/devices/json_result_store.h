#pragma once
/// @file
/// Test results in a JSON file that a clinician's tool reads and validates.

#include <optional>
#include <string>

#include "quiver/agents/devices/result_store.h"
#include "quiver/base/result.h"

namespace quiver::agents::devices {

/// Writes each result to one file, pretty JSON (test_result_json.h) with
/// `"validated_by_clinician": false`, atomically: `<path>.tmp` is written, fsynced and renamed
/// over `path` (then the directory is fsynced), so a reader always finds a whole file, the old
/// or the new. Not thread-safe; one store per file.
class JsonResultStore final : public ResultStore {
 public:
  explicit JsonResultStore(std::string path);

  /// @returns encode_test_result()'s errors, or kIo naming the file and the OS error when
  ///   writing, syncing or renaming fails (the previous file is then untouched).
  Status store(const TestResult& r) override;
  /// What this store last wrote (it does not read the file).
  std::optional<TestResult> last() const override { return last_; }

  const std::string& path() const { return path_; }

 private:
  std::string path_;
  std::optional<TestResult> last_;
};

/// Reads a result written by JsonResultStore.
/// @returns the result, or an error naming `path`: kNotFound (no such file), kIo (cannot read
///   it), decode_test_result()'s kMalformed (also naming the JSON pointer).
Result<TestResult> load_test_result(const std::string& path);

}  // namespace quiver::agents::devices
