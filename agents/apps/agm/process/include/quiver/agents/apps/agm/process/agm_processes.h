#pragma once
/// @file
/// The AGM agents as OS processes over DDS on loopback (`EXE run ROLE`, e.g. `quiver run
/// navigation`): started, killed -9 and restarted by role through the launcher `quiver launch`
/// uses (launcher.h), each with its output in OUT/logs/ROLE.log (every incarnation appended),
/// stopped with the final JSON status line it prints. The runs of agm_runs.h are built on it.
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "quiver/agents/runtime/process/process_host.h"
#include "quiver/agents/runtime/process/launcher.h"

namespace quiver::agents::inline apps::agm {

struct AgmProcessOptions {
  ProcessFlags dds;  ///< the domain and DDS configuration every process joins
  std::string exe;   ///< the executable whose `run ROLE` runs an agent (the quiver command)
  std::string out;   ///< logs go to OUT/logs; empty: a new directory /tmp/<prefix>-XXXXXX
};

class AgmProcesses {
 public:
  /// Logs go to o.out/logs (both made if need be; o.out must not be empty: out_dir()).
  explicit AgmProcesses(AgmProcessOptions o);
  /// SIGTERM to every process still running, then waits for them.
  ~AgmProcesses();
  AgmProcesses(const AgmProcesses&) = delete;
  AgmProcesses& operator=(const AgmProcesses&) = delete;

  /// Starts `role` with `extra` arguments after the DDS ones. False when it cannot.
  bool start(const std::string& role, std::vector<std::string> extra);
  /// kill -9 (and reap). @returns its pid, or -1.
  int kill(const std::string& role);
  /// Starts `role` again, with the arguments it had (a new incarnation, an empty replica).
  bool restart(const std::string& role) { return start(role, args_[role]); }
  /// SIGTERM, wait, and the last JSON line it printed (its final status), with its exit status
  /// as "exit_status" (-1: it did not end).
  std::optional<nlohmann::json> stop(const std::string& role);

 private:
  AgmProcessOptions o_;
  Launcher launcher_;
  std::map<std::string, std::vector<std::string>> args_;
};

}  // namespace quiver::agents::inline apps::agm
