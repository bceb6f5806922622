#pragma once
// What the AGM runs over DDS share: the observer replica that watches the agent processes and
// narrates what it sees, and the check of the agents' final status lines.
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "quiver/agents/apps/agm/process/agm_runs.h"

namespace quiver::agents::inline apps::agm::internal {

constexpr std::int64_t kMs = 1'000'000;
constexpr std::int64_t kSec = 1'000'000'000;

class ObservedRun {
 public:
  /// The observer's replica for run `r` (agm-observer, an observer: it writes nothing), its
  /// processes' logs in out_dir(r.processes.out, prefix); null (the reason logged) if it fails.
  /// The observer's replica, seeded with `world` as every agent of the run is: it holds the
  /// world even when it missed every agent's copy (published before DDS matched it).
  static std::unique_ptr<ObservedRun> open(const AgmDdsRun& r, const char* prefix, std::string_view world);
  DdsReplica& replica() { return *replica_; }
  graph::Graph& graph() { return replica_->graph(); }
  std::int64_t started_ns() const { return t_start_; }
  /// Seconds since open().
  double elapsed() const;
  /// Tells `on_edge` of every change to an edge from the robot the replica learns (once the
  /// robot is there), then `on_batch` (if any) of the whole batch.
  void watch(std::function<void(graph::NodeId robot, const graph::EdgeChange&)> on_edge,
             std::function<void()> on_batch = {});
  /// "[ 12.34 s] line" on stdout.
  void say(const std::string& line) const;
  /// Prints the run's first lines (`what` runs, `who`: over which domain, where the logs go) and
  /// starts the agents (role, arguments), in order. False (logged) when one cannot start.
  bool start(const std::string& what, const std::string& who,
             const std::vector<std::pair<std::string, std::vector<std::string>>>& agents);
  AgmProcesses& processes() { return *procs_; }
  /// Stops the tracker, then (once its last poses are everywhere) `roles`: their final status
  /// lines by role, and the tracker's in `humans`.
  std::map<std::string, nlohmann::json> stop(const std::vector<std::string>& roles,
                                             std::optional<nlohmann::json>& humans);
  /// Prints the failures and the verdict (`passed` when there are none). @returns the exit status.
  static int verdict(const std::vector<std::string>& failures, const char* passed);

 private:
  std::unique_ptr<DdsReplica> replica_;
  AgmProcessOptions options_;
  std::unique_ptr<AgmProcesses> procs_;  ///< stopped before the observer goes
  std::int64_t t_start_ = 0;
};

/// The agents' final status lines (`finals`, by role): each replica's digest equals the
/// observer's (`equal` says whether all did), all `expected` agents reported, and each (the
/// tracker's `humans` status too, added to `finals`) exited with status 0.
std::vector<std::string> final_status_failures(std::map<std::string, nlohmann::json>& finals,
                                               const std::string& digest, std::size_t expected,
                                               const std::optional<nlohmann::json>& humans,
                                               bool& equal);

inline void append(std::vector<std::string>& failures, const std::vector<std::string>& more) {
  failures.insert(failures.end(), more.begin(), more.end());
}

/// The two runs of run_agm_over_dds().
int run_route(const AgmDdsRun& r);
int run_clean_table(const AgmDdsRun& r);

}  // namespace quiver::agents::inline apps::agm::internal
