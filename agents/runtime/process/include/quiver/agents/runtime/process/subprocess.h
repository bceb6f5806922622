#pragma once
/// @file
/// Child processes with their stdout on a pipe: the agent processes that `quiver` starts (the
/// multi-process benchmarks and scenarios, agents/apps/*/process) and the tests start.

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <sys/stat.h>

#include <chrono>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

extern char** environ;

namespace quiver::agents::inline runtime {

class Subprocess {
 public:
  /// Starts `argv[0]` with the given arguments; its stdout is readable line by line, its stderr
  /// goes to ours.
  /// With `stderr_path`, its stderr goes to that file instead.
  static std::optional<Subprocess> spawn(const std::vector<std::string>& argv, const std::string& stderr_path = "") {
    int fds[2];
    if (pipe(fds) != 0) return std::nullopt;
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_adddup2(&fa, fds[1], STDOUT_FILENO);
    if (!stderr_path.empty())
      posix_spawn_file_actions_addopen(&fa, STDERR_FILENO, stderr_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addclose(&fa, fds[0]);
    posix_spawn_file_actions_addclose(&fa, fds[1]);
    std::vector<char*> args;
    for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    pid_t pid = 0;
    int rc = posix_spawn(&pid, args[0], &fa, nullptr, args.data(), environ);
    posix_spawn_file_actions_destroy(&fa);
    close(fds[1]);
    if (rc != 0) {
      close(fds[0]);
      return std::nullopt;
    }
    fcntl(fds[0], F_SETFL, fcntl(fds[0], F_GETFL) | O_NONBLOCK);
    Subprocess p;
    p.pid_ = pid;
    p.fd_ = fds[0];
    return p;
  }

  Subprocess() = default;
  Subprocess(Subprocess&& o) noexcept { *this = std::move(o); }
  Subprocess& operator=(Subprocess&& o) noexcept {
    std::swap(pid_, o.pid_);
    std::swap(fd_, o.fd_);
    std::swap(buf_, o.buf_);
    std::swap(status_, o.status_);
    return *this;
  }
  ~Subprocess() {
    if (pid_ > 0 && !status_) {
      ::kill(pid_, SIGKILL);
      int st;
      waitpid(pid_, &st, 0);
    }
    if (fd_ >= 0) close(fd_);
  }

  pid_t pid() const { return pid_; }

  /// The next complete stdout line, waiting up to `timeout_ms`; nullopt on timeout or EOF.
  std::optional<std::string> read_line(int timeout_ms) {
    auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
    for (;;) {
      auto nl = buf_.find('\n');
      if (nl != std::string::npos) {
        std::string line = buf_.substr(0, nl);
        buf_.erase(0, nl + 1);
        return line;
      }
      auto left = std::chrono::duration_cast<std::chrono::milliseconds>(end - std::chrono::steady_clock::now()).count();
      pollfd p{fd_, POLLIN, 0};
      // At least one (non-blocking) look at the pipe, even with a zero timeout.
      if (poll(&p, 1, static_cast<int>(std::max<long long>(left, 0))) <= 0) {
        if (left <= 0) return std::nullopt;
        continue;
      }
      char tmp[4096];
      ssize_t n = ::read(fd_, tmp, sizeof tmp);
      if (n == 0) return std::nullopt;  // EOF
      if (n > 0) buf_.append(tmp, static_cast<std::size_t>(n));
      else if (left <= 0) return std::nullopt;
    }
  }

  void kill(int sig) {
    if (pid_ > 0 && !status_) ::kill(pid_, sig);
  }
  /// Waits for the process to end (up to timeout_ms); its exit status, or -1 on timeout.
  int wait(int timeout_ms) {
    if (status_) return *status_;
    auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
    for (;;) {
      int st = 0;
      pid_t r = waitpid(pid_, &st, WNOHANG);
      if (r == pid_) {
        status_ = WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
        return *status_;
      }
      if (std::chrono::steady_clock::now() >= end) return -1;
      usleep(2000);
    }
  }

 private:
  pid_t pid_ = -1;
  int fd_ = -1;
  std::string buf_;
  std::optional<int> status_;
};

/// `out`, or a new directory /tmp/PREFIX-XXXXXX when it is empty ("/tmp" if none can be made):
/// where a multi-process run puts its logs and outputs.
inline std::string out_dir(const std::string& out, const char* prefix) {
  if (!out.empty()) return out;
  std::string tmpl = std::string("/tmp/") + prefix + "-XXXXXX";
  if (!mkdtemp(tmpl.data())) return "/tmp";
  return tmpl;
}

/// @returns the path of the running executable (to start its `run ROLE` subcommand), or
/// "quiver" when /proc/self/exe cannot be read.
inline std::string self_executable() {
  char buf[4096];
  const ssize_t n = readlink("/proc/self/exe", buf, sizeof buf - 1);
  return n > 0 ? std::string(buf, static_cast<std::size_t>(n)) : "quiver";
}

}  // namespace quiver::agents::inline runtime
