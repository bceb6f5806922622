// File writes that survive crashes: a whole file replaced atomically, one line appended and synced, and
// directories created with their parents.
#include "file_io.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <system_error>

namespace quiver::agents::devices::internal {
namespace {

Error io_error(const char* fn, const std::string& what, const std::string& path, int err) {
  return make_error(ErrorCode::kIo,
                    std::string(fn) + ": cannot " + what + " '" + path + "': " + errno_text(err));
}

// Writes all of `bytes`, retrying short writes and EINTR. Returns 0 or an errno value.
int write_all(int fd, std::string_view bytes) {
  while (!bytes.empty()) {
    ssize_t n = ::write(fd, bytes.data(), bytes.size());
    if (n < 0) {
      if (errno == EINTR) continue;
      return errno;
    }
    bytes.remove_prefix(static_cast<std::size_t>(n));
  }
  return 0;
}

std::string parent_dir(const std::string& path) {
  std::filesystem::path parent = std::filesystem::path(path).parent_path();
  return parent.empty() ? std::string(".") : parent.string();
}

}  // namespace

std::string errno_text(int err) {
  std::error_code ec(err, std::generic_category());
  return ec.message();
}

Status write_file_atomically(const std::string& path, std::string_view bytes, const char* fn) {
  const std::string tmp = path + ".tmp";
  int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) return io_error(fn, "create", tmp, errno);
  auto fail = [&](const char* what, int err) -> Status {
    if (fd >= 0) ::close(fd);
    ::unlink(tmp.c_str());
    return io_error(fn, what, tmp, err);
  };
  if (int err = write_all(fd, bytes); err != 0) return fail("write", err);
  if (::fsync(fd) != 0) return fail("fsync", errno);
  int rc = ::close(fd);
  fd = -1;
  if (rc != 0) return fail("close", errno);
  if (::rename(tmp.c_str(), path.c_str()) != 0) {
    int err = errno;
    ::unlink(tmp.c_str());
    return make_error(ErrorCode::kIo, std::string(fn) + ": cannot rename '" + tmp + "' to '" +
                                          path + "': " + errno_text(err));
  }
  // The rename is durable only once the directory is synced.
  const std::string dir = parent_dir(path);
  int dfd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dfd < 0) return io_error(fn, "open the directory", dir, errno);
  int sync_rc = ::fsync(dfd);
  int sync_err = errno;
  ::close(dfd);
  if (sync_rc != 0) return io_error(fn, "fsync the directory", dir, sync_err);
  return Status::Ok();
}

Status append_synced(const std::string& path, std::string_view line, const char* fn) {
  int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  if (fd < 0) return io_error(fn, "open", path, errno);
  // One write() per line: concurrent appenders (and a tailing reader) see whole lines.
  ssize_t n;
  do {
    n = ::write(fd, line.data(), line.size());
  } while (n < 0 && errno == EINTR);
  int err = errno;
  if (n < 0) {
    ::close(fd);
    return io_error(fn, "append to", path, err);
  }
  if (static_cast<std::size_t>(n) != line.size()) {
    ::close(fd);
    return make_error(ErrorCode::kIo, std::string(fn) + ": short write to '" + path + "': " +
                                          std::to_string(n) + " of " +
                                          std::to_string(line.size()) + " bytes");
  }
  if (::fsync(fd) != 0) {
    err = errno;
    ::close(fd);
    return io_error(fn, "fsync", path, err);
  }
  if (::close(fd) != 0) return io_error(fn, "close", path, errno);
  return Status::Ok();
}

Status ensure_directory(const std::string& dir, const char* fn) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) {
    return make_error(ErrorCode::kIo,
                      std::string(fn) + ": cannot create directory '" + dir + "': " + ec.message());
  }
  if (!std::filesystem::is_directory(dir, ec)) {
    return make_error(ErrorCode::kIo, std::string(fn) + ": '" + dir + "' is not a directory");
  }
  return Status::Ok();
}

}  // namespace quiver::agents::devices::internal
