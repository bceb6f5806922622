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
#include <utility>
#include <vector>

extern char** environ;

namespace quiver::agents::inline runtime {

/// How Subprocess::spawn() starts a process.
struct SpawnOptions {
  std::string stderr_path;  ///< its stderr goes to this file (empty: to ours)
  bool append = false;      ///< append to stderr_path rather than truncate it
  /// Added to our environment (replacing a variable of the same name).
  std::vector<std::pair<std::string, std::string>> env;
  bool own_group = false;    ///< its own process group: a Ctrl-C at the terminal reaches only us
  bool search_path = false;  ///< an argv[0] without '/' is looked up in PATH
  bool null_stdin = true;    ///< its stdin is /dev/null (else ours)
};

class Subprocess {
 public:
  /// Starts `argv[0]` with the given arguments; its stdout is readable line by line, its stderr
  /// goes to ours.
  /// With `stderr_path`, its stderr goes to that file instead.
  static std::optional<Subprocess> spawn(const std::vector<std::string>& argv, const std::string& stderr_path = "") {
    SpawnOptions o;
    o.stderr_path = stderr_path;
    o.null_stdin = false;
    return spawn(argv, o);
  }
  /// The same with options. `error` (if given) receives posix_spawn's error
  /// number when it fails.
  static std::optional<Subprocess> spawn(const std::vector<std::string>& argv, const SpawnOptions& o,
                                         int* error = nullptr) {
    int fds[2];
    if (argv.empty() || pipe(fds) != 0) return std::nullopt;
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_adddup2(&fa, fds[1], STDOUT_FILENO);
    if (!o.stderr_path.empty())
      posix_spawn_file_actions_addopen(&fa, STDERR_FILENO, o.stderr_path.c_str(),
                                       O_WRONLY | O_CREAT | (o.append ? O_APPEND : O_TRUNC), 0644);
    if (o.null_stdin) posix_spawn_file_actions_addopen(&fa, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addclose(&fa, fds[0]);
    posix_spawn_file_actions_addclose(&fa, fds[1]);
    std::vector<char*> args;
    for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    std::vector<std::string> env;
    for (char** e = environ; *e != nullptr; ++e) {
      std::string kv = *e;
      const std::string key = kv.substr(0, kv.find('='));
      bool replaced = false;
      for (const auto& [k, v] : o.env) replaced = replaced || k == key;
      if (!replaced) env.push_back(std::move(kv));
    }
    for (const auto& [k, v] : o.env) env.push_back(k + "=" + v);
    std::vector<char*> envp;
    for (auto& s : env) envp.push_back(s.data());
    envp.push_back(nullptr);
    posix_spawnattr_t attr;
    posix_spawnattr_init(&attr);
    if (o.own_group) {
      posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETPGROUP);
      posix_spawnattr_setpgroup(&attr, 0);
    }
    pid_t pid = 0;
    const bool search = o.search_path && argv[0].find('/') == std::string::npos;
    int rc = search ? posix_spawnp(&pid, args[0], &fa, &attr, args.data(), envp.data())
                    : posix_spawn(&pid, args[0], &fa, &attr, args.data(), envp.data());
    posix_spawn_file_actions_destroy(&fa);
    posix_spawnattr_destroy(&attr);
    close(fds[1]);
    if (rc != 0) {
      close(fds[0]);
      if (error != nullptr) *error = rc;
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

/// @returns the path of the executable `name` in the running executable's folder (the lean
/// per-role executables built beside `quiver`, e.g. quiver-barthel), or nullopt when it is not there.
inline std::optional<std::string> sibling_executable(const std::string& name) {
  const std::string self = self_executable();
  const std::size_t slash = self.rfind('/');
  if (slash == std::string::npos) return std::nullopt;
  std::string sibling = self.substr(0, slash + 1) + name;
  if (access(sibling.c_str(), X_OK) != 0) return std::nullopt;
  return sibling;
}

/// @returns sibling_executable(name) when it is there, else self_executable().
inline std::string sibling_or_self(const std::string& name) {
  return sibling_executable(name).value_or(self_executable());
}

}  // namespace quiver::agents::inline runtime
