// Joining a live DDS domain as an observer and waiting until it holds the shared graph.
#include "observer.h"

#include <cstdio>

namespace quiver::tools {

Result<std::unique_ptr<agents::DdsReplica>> open_observer(const DdsFlags& dds,
                                                          const std::string& name,
                                                          ObserverMode mode) {
  agents::DdsReplicaOptions o;
  o.name = name;
  o.observer = true;
  o.dds.best_effort_reader = mode.best_effort;
  o.replicator.sample_ns = mode.sample_ns;
  o.replicator.sample_bytes_per_s = mode.sample_bytes_per_s;
  return dds.create_agent(o);
}

Status wait_for_graph(agents::DdsReplica& a, const DdsFlags& dds, double timeout_s) {
  const std::int64_t timeout = static_cast<std::int64_t>(timeout_s * 1e9);
  char seconds[32];
  std::snprintf(seconds, sizeof seconds, "%.1f s", timeout_s);
  if (!a.spin_until([&] { return a.replicator().live_peer_count() > 0; }, timeout))
    return make_error(ErrorCode::kTimeout, "no agent answered on DDS domain " +
                                               std::to_string(dds.domain) + " within " + seconds);
  // Synced = we hold everything every live peer says it holds; require it to stay so briefly.
  std::int64_t synced_since = -1;
  const bool ok = a.spin_until(
      [&] {
        if (!a.replicator().synced()) {
          synced_since = -1;
          return false;
        }
        if (synced_since < 0) synced_since = agents::monotonic_ns();
        return agents::monotonic_ns() - synced_since > 150'000'000;
      },
      timeout);
  if (!ok)
    return make_error(ErrorCode::kTimeout, "could not sync with the " +
                                               std::to_string(a.replicator().live_peer_count()) +
                                               " live agents within " + seconds);
  return {};
}

Result<std::unique_ptr<agents::DdsReplica>> join_as_observer(const DdsFlags& dds,
                                                             const std::string& name,
                                                             double timeout_s) {
  auto created = open_observer(dds, name);
  if (!created.ok()) return created.error();
  if (Status s = wait_for_graph(**created, dds, timeout_s); !s.ok()) return s.error();
  return created;
}

}  // namespace quiver::tools
