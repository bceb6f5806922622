// Running a program to completion without a shell (posix_spawnp), with its output captured and how it ended.
#include "run_program.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>

#include "file_io.h"

extern char** environ;

namespace quiver::agents::devices::internal {

std::string quote_command(const std::vector<std::string>& argv) {
  std::string out;
  for (const std::string& a : argv) {
    if (!out.empty()) out += ' ';
    bool plain = !a.empty() && a.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                                   "0123456789_-./=:,+%@") == std::string::npos;
    if (plain) {
      out += a;
      continue;
    }
    out += '\'';
    for (char c : a) {
      if (c == '\'') {
        out += "'\\''";
      } else {
        out += c;
      }
    }
    out += '\'';
  }
  return out;
}

Result<ProgramExit> run_program(const std::vector<std::string>& argv, const char* fn) {
  const std::string command = quote_command(argv);
  auto io_error = [&](const std::string& what, int err) {
    return make_error(ErrorCode::kIo,
                      std::string(fn) + ": " + what + " '" + command + "': " + errno_text(err));
  };

  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) return io_error("cannot create a pipe for", errno);

  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_adddup2(&actions, fds[1], STDOUT_FILENO);
  posix_spawn_file_actions_adddup2(&actions, fds[1], STDERR_FILENO);

  std::vector<char*> args;
  args.reserve(argv.size() + 1);
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);

  pid_t pid = 0;
  int rc = ::posix_spawnp(&pid, args[0], &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  ::close(fds[1]);
  if (rc != 0) {
    ::close(fds[0]);
    if (rc == ENOENT) {
      return make_error(ErrorCode::kNotFound, std::string(fn) + ": cannot run '" + command +
                                                  "': program '" + argv[0] + "' not found");
    }
    return io_error("cannot run", rc);
  }

  // Drain the pipe until the child closes it, keeping the first kMaxCapturedOutput bytes.
  ProgramExit result;
  char buf[4096];
  for (;;) {
    ssize_t n = ::read(fds[0], buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    std::size_t room = kMaxCapturedOutput - result.output.size();
    result.output.append(buf, std::min(room, static_cast<std::size_t>(n)));
  }
  ::close(fds[0]);

  int status = 0;
  pid_t waited;
  do {
    waited = ::waitpid(pid, &status, 0);
  } while (waited < 0 && errno == EINTR);
  if (waited < 0) return io_error("cannot wait for", errno);
  if (WIFEXITED(status)) {
    result.exited = true;
    result.code = WEXITSTATUS(status);
  } else {
    result.exited = false;
    result.code = WIFSIGNALED(status) ? WTERMSIG(status) : 0;
  }
  return result;
}

}  // namespace quiver::agents::devices::internal
