// What a process logs about its replica: rejected input and membership, rate-limited by kind.
#include "quiver/agents/runtime/process/replica_reports.h"

#include "quiver/agents/runtime/process/dds_replica.h"

namespace quiver::agents::inline runtime {

ReplicaReports::ReplicaReports(std::shared_ptr<spdlog::logger> log, std::string prefix)
    : log_(std::move(log)),
      prefix_(std::move(prefix)),
      errors_([this](const std::string& line) { log_->warn("{}rejected: {}", prefix_, line); }),
      membership_([this](const std::string& line) { log_->info("{}{}", prefix_, line); }, 5'000'000'000, 8) {}

void ReplicaReports::attach(Replicator& r) {
  r.on_error([this](const Error& e) { report(e); });
  r.on_membership([this](Membership m, const PeerInfo& p) {
    const char* what = m == Membership::kJoined ? "joined" : "left";
    membership_.report(what, std::string(what) + ": " + p.name + " (" + p.id.to_string() + ")", monotonic_ns());
  });
}

void ReplicaReports::report(const Error& e) {
  std::lock_guard<std::mutex> lock(errors_mu_);
  errors_.report(e, monotonic_ns());
}

void ReplicaReports::tick(std::int64_t now_ns) {
  {
    std::lock_guard<std::mutex> lock(errors_mu_);
    errors_.tick(now_ns);
  }
  membership_.tick(now_ns);
}

}  // namespace quiver::agents
