#pragma once
/// @file
/// A launch file (`quiver launch FILE`, docs/agents.md "Launching a set of agents"): the agents
/// to start together, each a process with its command, arguments, environment and restart
/// policy, and the folder their logs go to. JSON, read with nlohmann/json.

#include <map>
#include <string>
#include <vector>

#include "quiver/base/result.h"

namespace quiver::agents::inline runtime {

enum class Restart { kNever, kOnFailure, kAlways };

struct LaunchAgent {
  std::string name;                ///< names its log file (NAME.log)
  std::string command;             ///< empty: this quiver executable
  std::vector<std::string> args;
  std::map<std::string, std::string> env;
  Restart restart = Restart::kNever;
  int max_restarts = 5;
  double restart_delay_s = 1;
  double start_after_s = 0;
};

struct LaunchFile {
  std::vector<LaunchAgent> agents;
  std::string logs;  ///< the logs' folder as written (relative paths: to the file's folder)
  double stop_grace_s = 5;
};

/// Reads a launch file. @returns kIo if it cannot be read, kMalformed naming the field at fault.
Result<LaunchFile> load_launch_file(const std::string& path);

}  // namespace quiver::agents::inline runtime
