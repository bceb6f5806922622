// Test results in a JSON file, replaced atomically on every store, and read back.
#include "quiver/agents/devices/json_result_store.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <utility>

#include "file_io.h"
#include "quiver/agents/devices/test_result_json.h"
#include "test_result_json_internal.h"

namespace quiver::agents::devices {

JsonResultStore::JsonResultStore(std::string path) : path_(std::move(path)) {}

Status JsonResultStore::store(const TestResult& r) {
  constexpr const char* kFn = "JsonResultStore::store()";
  Result<std::string> text = encode_test_result(r, kFn);
  if (!text) return text.error();
  if (Status s = internal::write_file_atomically(path_, *text, kFn); !s) return s;
  last_ = r;
  return Status::Ok();
}

Result<TestResult> load_test_result(const std::string& path) {
  constexpr const char* kFn = "load_test_result()";
  int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    const int err = errno;
    return make_error(err == ENOENT ? ErrorCode::kNotFound : ErrorCode::kIo,
                      std::string(kFn) + ": cannot open '" + path + "': " +
                          internal::errno_text(err));
  }
  std::string text;
  char buf[8192];
  for (;;) {
    ssize_t n = ::read(fd, buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      const int err = errno;
      ::close(fd);
      return make_error(ErrorCode::kIo, std::string(kFn) + ": cannot read '" + path + "': " +
                                            internal::errno_text(err));
    }
    if (n == 0) break;
    text.append(buf, static_cast<std::size_t>(n));
  }
  ::close(fd);
  return internal::decode_test_result(text, path, kFn);
}

}  // namespace quiver::agents::devices
