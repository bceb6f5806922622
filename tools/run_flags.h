#pragma once
// `run ROLE`: its flags, and the roles another app adds beside the Barthel test's (the AGM
// roles in `quiver`; quiver-barthel has the Barthel roles only).

#include <CLI/CLI.hpp>

#include <cstdint>
#include <functional>
#include <string>

#include "quiver/agents/runtime/process/process_host.h"

namespace quiver::tools {

struct RunFlags {
  agents::ProcessFlags process;
  std::string role, out, script, name;
  std::uint64_t patient_seed = 1;
  bool simulated_speech = false;
  double answer_timeout_s = 8;
  double words_ms = 250;
  bool measure_humans = false;
  bool quiet_when_done = false;
  std::string mission;
  /// AGM in a team (docs/teams.md): the robot this agent works for, the team's size, and the
  /// directory of the hands' custody shared by the robots' processes.
  std::string team_robot, custody;
  int robots = 2;
};

/// Roles that `run` accepts beside the Barthel test's; empty: none.
struct ExtraRoles {
  std::string help;                                       ///< appended to the role's help text
  std::string names;                                      ///< for the error on an unknown role
  std::function<void(CLI::App*, RunFlags&)> add_options;  ///< their own options of `run`
  std::function<bool(const std::string&)> has;
  std::function<int(RunFlags)> run;
};

}  // namespace quiver::tools
