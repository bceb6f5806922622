#pragma once
/// @file
/// The observer replica of a process run (agents/apps/*/process): a replica that watches the
/// agent processes and commits nothing, opened with the caller's DDS flags.
#include <memory>
#include <string>

#include "quiver/agents/runtime/process/dds_replica.h"

namespace quiver::agents::inline runtime {

/// Opens an observer replica called `name` with `open`. When it cannot, logs why under the
/// logger `who`. Any thread.
/// @returns the replica, or null when it could not be opened.
std::unique_ptr<DdsReplica> open_observer_replica(const ReplicaFactory& open,
                                                  const std::string& name, const std::string& who);

}  // namespace quiver::agents::inline runtime
