// Who holds each object: in one process (SharedCustody) or across processes (FileCustody).
#include "quiver/agents/apps/agm/custody.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>

namespace quiver::agents::inline apps::agm {

bool SharedCustody::take(const std::string& object, const std::string& robot) {
  auto [it, fresh] = held_.emplace(object, robot);
  return fresh || it->second == robot;
}

void SharedCustody::put(const std::string& object, const std::string& robot) {
  auto it = held_.find(object);
  if (it != held_.end() && it->second == robot) it->second.clear();
}

std::string SharedCustody::holder(const std::string& object) const {
  auto it = held_.find(object);
  return it == held_.end() ? std::string() : it->second;
}

Result<std::unique_ptr<FileCustody>> FileCustody::open(const std::string& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) return make_error(ErrorCode::kIo, "custody directory '" + dir + "': " + ec.message());
  return std::unique_ptr<FileCustody>(new FileCustody(dir));
}

std::string FileCustody::path(const std::string& object) const { return dir_ + "/" + object; }

std::string FileCustody::read(const std::string& object) const {
  std::ifstream in(path(object));
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

bool FileCustody::take(const std::string& object, const std::string& robot) {
  // O_EXCL: of two hands closing at once, one creates the file; the other finds it.
  const int fd = ::open(path(object).c_str(), O_WRONLY | O_CREAT | O_EXCL, 0644);
  if (fd < 0) return errno == EEXIST && read(object) == robot;
  const bool ok = ::write(fd, robot.data(), robot.size()) == static_cast<ssize_t>(robot.size());
  ::fsync(fd);
  ::close(fd);
  return ok;
}

void FileCustody::put(const std::string& object, const std::string& robot) {
  if (read(object) != robot) return;
  std::ofstream(path(object), std::ios::trunc).flush();  // put down: empty, and not to be taken again
}

std::string FileCustody::holder(const std::string& object) const { return read(object); }

}  // namespace quiver::agents::inline apps::agm
