#pragma once
/// @file
/// The one logger setup of Quiver's programs (agent processes and the `quiver` command): spdlog
/// on stderr, one line per message, "HH:MM:SS.mmm [name] level: message", where the name is the
/// agent's (or the command's). Libraries do not log; they return errors, and programs log them.
#include <memory>
#include <string>
#include <string_view>

#include <spdlog/logger.h>

namespace quiver::agents::inline runtime {

/// The logger of this name, made on first use at the current level.
/// @returns the logger (registered with spdlog; it writes to stderr, thread-safely).
/// @throws spdlog::spdlog_ex if another thread registers the same new name at the same time
///         (make a name's first logger on one thread).
std::shared_ptr<spdlog::logger> named_logger(const std::string& name);

/// Sets the level of every logger, now and later: trace, debug, info, warn, error, critical or
/// off. @returns false (and changes nothing) for any other word. Thread-safe.
bool set_log_level(std::string_view level);

}  // namespace quiver::agents
