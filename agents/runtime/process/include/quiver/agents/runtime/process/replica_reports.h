#pragma once
/// @file
/// What a process logs about its replica: rejected input (a hostile peer can cause thousands of
/// bad packets and invented peers a second: one line per kind, then a count every few seconds)
/// and peers joining and leaving (rate-limited alike). Shared by agent processes and gateways.
///
/// Threading: report() is thread-safe (Cyclone's log lines come from its threads); attach() and
/// tick() belong to the replica's owner thread.

#include <cstdint>
#include <memory>
#include <mutex>
#include <string>

#include <spdlog/logger.h>

#include "quiver/agents/replica/replication/error_limiter.h"
#include "quiver/agents/replica/replication/replicator.h"

namespace quiver::agents::inline runtime {

class ReplicaReports {
 public:
  /// Lines go to `log`, each after `prefix` (e.g. "team: " for a gateway's second replica).
  explicit ReplicaReports(std::shared_ptr<spdlog::logger> log, std::string prefix = "");
  ReplicaReports(const ReplicaReports&) = delete;
  ReplicaReports& operator=(const ReplicaReports&) = delete;
  /// Reports `r`'s rejected input and membership from now on (its on_error and on_membership
  /// callbacks). @pre this object outlives `r`'s use of them.
  void attach(Replicator& r);
  /// A rejected input (or a transport's own error line). Thread-safe.
  void report(const Error& e);
  /// Emits the counts of kinds whose period ended. Owner thread.
  void tick(std::int64_t now_ns);

 private:
  std::shared_ptr<spdlog::logger> log_;
  std::string prefix_;
  std::mutex errors_mu_;
  ErrorLimiter errors_;      // guarded by errors_mu_
  ErrorLimiter membership_;  // owner thread
};

}  // namespace quiver::agents
