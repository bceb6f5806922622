#pragma once
/// @file
/// A scenario's fault schedule played on an AgentHost: partitions, heals, kill -9, restarts and
/// packet loss at their times.

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "quiver/sim/agent_host.h"
#include "quiver/sim/scenario.h"

namespace quiver::sim {

/// Schedules every event of `faults` on `host` (its clock). Each is logged through `log` (may be
/// null) when it happens; `partitions` and `kills` count those that took effect (a kill of an
/// agent that is already down does nothing and is not counted). The counters must outlive the run.
void schedule_faults(AgentHost& host, const std::vector<FaultEvent>& faults,
                     std::function<void(std::int64_t, const std::string&)> log, int& partitions, int& kills);

}  // namespace quiver::sim
