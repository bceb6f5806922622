#pragma once
/// @file
/// The Barthel agents as one OS process each (`EXE run ROLE`), over DDS on loopback: started,
/// killed and restarted by name through the launcher `quiver launch` uses (launcher.h), their
/// output logged in OUT/logs/NAME.log. The runs of barthel_runs.h (`quiver scenario barthel`,
/// `quiver bench reaction`) are built on it.
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "quiver/agents/runtime/process/launcher.h"

namespace quiver::agents::inline apps::barthel {

struct BarthelProcessOptions {
  std::uint32_t domain = 0;
  std::string dds_config = "loopback";
  std::string exe;          ///< the executable whose `run ROLE` runs an agent (the quiver command)
  std::string out;          ///< devices write here; logs go to out/logs
  std::string script_path;  ///< the patient's script (JSON)
  double answer_timeout_s = 8;
  bool simulated_speech = false;
  double words_ms = 250;
};

class BarthelProcesses {
 public:
  /// Makes o.out and o.out/logs. While it lives, SIGINT and SIGTERM stop its agents first.
  explicit BarthelProcesses(BarthelProcessOptions o);
  ~BarthelProcesses();
  BarthelProcesses(const BarthelProcesses&) = delete;
  BarthelProcesses& operator=(const BarthelProcesses&) = delete;

  /// Starts (or restarts) `role` as the agent `name` (default: the role). False when it cannot.
  bool start(const std::string& role, const std::string& name = "");
  /// Sends `sig` to the agent `name` and, for SIGKILL, reaps it. @returns its pid, or -1.
  int kill(const std::string& name, int sig);
  /// SIGTERM to every agent, then waits for them (each prints its final status line).
  void stop_all();
  /// The last JSON status line agent `name` printed on stdout (after stop_all: its final one).
  std::optional<nlohmann::json> last_status(const std::string& name);

 private:
  std::vector<std::string> argv_of(const std::string& role, const std::string& name) const;
  BarthelProcessOptions o_;
  Launcher launcher_;
};

}  // namespace quiver::agents::inline apps::barthel
