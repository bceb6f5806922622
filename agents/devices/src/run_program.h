#pragma once
// Runs a program to completion without a shell, capturing what it prints.

#include <string>
#include <vector>

#include "quiver/base/result.h"

namespace quiver::agents::devices::internal {

/// How a program ended.
struct ProgramExit {
  bool exited = false;   ///< true: it called exit(); false: a signal killed it
  int code = 0;          ///< the exit status, or the signal number
  std::string output;    ///< its stdout and stderr, interleaved, at most kMaxCapturedOutput bytes
};

inline constexpr std::size_t kMaxCapturedOutput = 4096;

/// Starts `argv[0]` (looked up in PATH unless it holds a '/') with `argv` via posix_spawnp,
/// stdin from /dev/null, stdout and stderr on a pipe, and waits for it to end.
/// @pre !argv.empty().
/// @returns how it ended, or an error naming `fn` and the command: kNotFound when the program
///   does not exist, kIo when it cannot be started or waited for.
Result<ProgramExit> run_program(const std::vector<std::string>& argv, const char* fn);

/// `argv` as a shell would show it, each argument quoted when needed (for messages only).
std::string quote_command(const std::vector<std::string>& argv);

}  // namespace quiver::agents::devices::internal
