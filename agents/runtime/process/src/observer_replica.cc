// The observer replica of a process run: opened with the caller's DDS flags, or the reason logged.
#include "quiver/agents/runtime/process/observer_replica.h"

#include "quiver/agents/runtime/process/logging.h"

namespace quiver::agents::inline runtime {

std::unique_ptr<DdsReplica> open_observer_replica(const ReplicaFactory& open,
                                                  const std::string& name, const std::string& who) {
  DdsReplicaOptions o;
  o.name = name;
  o.observer = true;
  auto created = open(std::move(o));
  if (!created.ok()) {
    named_logger(who)->error("{}", created.error().to_string());
    return nullptr;
  }
  return std::move(*created);
}

}  // namespace quiver::agents::inline runtime
