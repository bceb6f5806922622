#pragma once
/// @file
/// A set of agent processes started and supervised together: the agents of a launch file
/// (`quiver launch`) and those of the multi-process scenarios (`quiver scenario barthel|agm`).
/// Each agent is one OS process (this executable, or another program) with its arguments and
/// environment; its stderr and stdout go to LOGS/NAME.log (appended across its starts), and the
/// last JSON status line it printed on stdout is kept. A restart policy (launch_file.h) restarts
/// an agent that ended; one clean stop for all sends SIGTERM (each agent hands over and leaves),
/// then SIGKILL after a grace.
///
/// Threading: one thread. poll() (or last_status()) must run now and then (every ~50 ms while
/// agents print a lot): it copies what they print to their logs, so that no pipe fills.

#include <sys/types.h>

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "quiver/agents/runtime/process/launch_file.h"
#include "quiver/agents/runtime/process/subprocess.h"

namespace quiver::agents::inline runtime {

class Launcher {
 public:
  /// `logs`: the folder of the agents' logs (made if missing). `self`: what an agent without a
  /// command runs (this executable).
  explicit Launcher(std::string logs, std::string self = self_executable());
  /// Kills (SIGKILL) and reaps what still runs.
  ~Launcher();
  Launcher(const Launcher&) = delete;
  Launcher& operator=(const Launcher&) = delete;

  /// Starts agent `a` now, or a.start_after_s from now; an agent of that name that runs is
  /// replaced (killed first). @returns kIo naming the agent and why when it cannot start now.
  Status start(LaunchAgent a);
  /// Starts the agents whose time came, restarts ended ones as their policy says, and copies
  /// what they printed to their logs.
  void poll();
  /// Agents running, and agents waiting to start (or to be restarted).
  int running() const;
  int pending() const;
  /// Sends `sig` to agent `name`; for SIGKILL, waits until it is gone (it is not restarted).
  /// @returns its pid, or -1 if no such agent runs.
  int kill(const std::string& name, int sig);
  /// Stops agent `name` cleanly (SIGTERM; SIGKILL after `grace_s`) and forgets it.
  /// @returns its last status line with "exit_status" added, or nullopt if it printed none.
  std::optional<nlohmann::json> stop(const std::string& name, double grace_s = 5);
  /// SIGTERM to every agent, SIGKILL to those still running after `grace_s`; none is restarted.
  void stop_all(double grace_s);
  /// The last JSON line agent `name` printed on stdout (after a stop: its final one).
  std::optional<nlohmann::json> last_status(const std::string& name);
  /// Every agent's pid (0: not running), for a signal handler.
  std::map<std::string, pid_t> pids() const;

  struct Record {
    int starts = 0;
    int last_status = -1;  ///< the last exit status (128 + signal when killed); -1: none yet
    bool failed_to_start = false;
  };
  /// Every agent's starts and last exit status, by name.
  std::map<std::string, Record> records() const;
  /// What the launcher does (started, ended, restarting), for a log: `warn` for what went wrong.
  void on_note(std::function<void(bool warn, const std::string&)> fn) { note_ = std::move(fn); }

 private:
  struct Agent;
  Status spawn(Agent& a);
  void drain(Agent& a);
  void reaped(Agent& a, int status, bool stopping);
  void note(bool warn, const std::string& s) {
    if (note_) note_(warn, s);
  }
  std::string logs_, self_;
  std::map<std::string, std::unique_ptr<Agent>> agents_;
  bool stopping_ = false;
  std::function<void(bool, const std::string&)> note_;
};

}  // namespace quiver::agents::inline runtime
