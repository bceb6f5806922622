#pragma once
/// @file
/// The observer replica of a process run (agents/apps/*/process): a replica that watches the
/// agent processes and commits nothing, opened with the caller's DDS flags.
#include <memory>
#include <string>
#include <string_view>

#include "quiver/agents/runtime/process/dds_replica.h"

namespace quiver::agents::inline runtime {

/// Opens an observer replica called `name` with `open` and seeds it with `world` (the text of the
/// world file the agents seed; empty: none). When it cannot, logs why under the logger `who`.
/// Any thread.
///
/// Seeding it as the agents do matters: the agents publish the world as they start, before DDS
/// has matched the observer's reader, and the world's origin never changes again, so a missed seed
/// shows in no gap. While the agents keep changing, set hashes and counts then hide it (docs/
/// protocol.md, "stale_pull_ns"): one CI run's observer saw nothing of a Barthel run for 35 s.
/// @returns the replica, or null when it could not be opened or seeded.
std::unique_ptr<DdsReplica> open_observer_replica(const ReplicaFactory& open, const std::string& name,
                                                  const std::string& who, std::string_view world = {});

}  // namespace quiver::agents::inline runtime
