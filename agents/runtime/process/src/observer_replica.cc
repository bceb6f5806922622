// The observer replica of a process run: opened with the caller's DDS flags, or the reason logged.
#include "quiver/agents/runtime/process/observer_replica.h"

#include "quiver/agents/runtime/process/logging.h"
#include "quiver/graph/world_file.h"

namespace quiver::agents::inline runtime {

std::unique_ptr<DdsReplica> open_observer_replica(const ReplicaFactory& open, const std::string& name,
                                                  const std::string& who, std::string_view world) {
  DdsReplicaOptions o;
  o.name = name;
  o.observer = true;
  auto created = open(std::move(o));
  if (!created.ok()) {
    named_logger(who)->error("{}", created.error().to_string());
    return nullptr;
  }
  if (world.empty()) return std::move(*created);
  // The same label as the agents' (process_host.cc): the seed depends only on the text.
  auto seed = graph::world_seed(world, "embedded world");
  if (!seed.ok()) {
    named_logger(who)->error("cannot seed the observer: {}", seed.error().to_string());
    return nullptr;
  }
  if (auto s = (*created)->replicator().seed(seed->delta); !s.ok()) {
    named_logger(who)->error("cannot seed the observer: {}", s.error().to_string());
    return nullptr;
  }
  return std::move(*created);
}

}  // namespace quiver::agents::inline runtime
