#pragma once
/// @file
/// The AGM runs over DDS, one process per agent (AgmProcesses), each watched from an observer
/// replica that narrates on stdout what it sees happen and checks at the end what the simulator
/// checks too (agents/apps/agm/agm_checks.h), with the platform's truth replayed from what the
/// navigation agent wrote: `quiver scenario agm [--mission clean-table]`. And the human-tracking
/// benchmark (`quiver bench humans`): how fresh the joints are when they reach the other agents.
#include <functional>
#include <memory>
#include <string>

#include "quiver/agents/apps/agm/process/agm_processes.h"
#include "quiver/agents/runtime/process/dds_replica.h"
#include "quiver/base/result.h"

namespace quiver::agents::inline apps::agm {

struct AgmDdsRun {
  AgmProcessOptions processes;
  ReplicaFactory observer;  ///< opens the observer's replica
  double timeout_s = 150;            ///< give up after this
  double crossing_lag_ms = 100;      ///< changeRoom committed within this of its pose
  double motion_allowance_ms = 150;  ///< a grasp ends within this of the platform moving
  /// kill -9 this agent at kill_at_s and restart it restart_after_s later (fixed route only).
  std::string kill;
  double kill_at_s = 12, restart_after_s = 1;
  /// "" (the fixed route: navigation, rooms, grasping, humans) or kCleanTable (the planner agent
  /// as a fifth process; navigation and grasping follow its plan).
  std::string mission;
};

/// Runs it (out directory default: /tmp/quiver-agm-*). @returns the exit status: 0 when every
/// check holds, 1 when one fails, 2 when it cannot start.
int run_agm_over_dds(const AgmDdsRun& r);

struct HumansBench {
  AgmProcessOptions processes;
  double seconds = 10;     ///< how long the tracker runs
  double max_p99_ms = 10;  ///< fail above this latency
  /// Without the planner agent: the fixed route (default: the clean-the-table mission).
  bool no_planner = false;
};

/// Human tracking (2 people x 15 joints x 30 Hz) reaching the navigation, rooms, grasping (and
/// planner) agents while they work: prints one JSON line of latency p50/p99/max and rates on
/// stdout. @returns 0 when every agent exited cleanly and the p99 is within bounds, 1 if not, 2
/// when it cannot start.
int run_humans_bench(const HumansBench& b);

}  // namespace quiver::agents::inline apps::agm
