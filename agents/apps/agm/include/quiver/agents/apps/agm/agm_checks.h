#pragma once
/// @file
/// What must hold in an AGM run, written once for both hosts that run it: the simulator
/// (agents/apps/agm/sim) and the agent processes over DDS checked from an observer replica
/// (agents/apps/agm/process). Each check takes what its host saw — the final replica, the
/// platform's true path (the simulator's device; over DDS, replayed from what the navigation
/// agent wrote), the room changes and grasp events the agents made — and returns what failed, one
/// sentence each (empty: it holds).
#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "quiver/agents/apps/agm/grasping.h"
#include "quiver/agents/apps/agm/platform.h"
#include "quiver/agents/apps/agm/rooms.h"
#include "quiver/graph/graph.h"

namespace quiver::agents::inline apps::agm {

/// A virtual or monotonic time in a check's sentence: "12.345 s".
std::string seconds_text(std::int64_t t_ns);

/// The final replica's facts. The fixed route (`mission` ""): the robot ends in the kitchen
/// carrying the mug, the mug in the kitchen too and only in reach. Clean the table
/// (kCleanTable): the mission holds and the plan node says achieved. Both: the robot is parked
/// (no movedInLastSeconds) and announces no grasp.
std::vector<std::string> end_state_failures(const graph::Graph& g, std::string_view mission);

/// One crossing of a room limit: from, to.
using Crossing = std::pair<std::string, std::string>;
/// The room limits (rooms of `g`) the platform's true path crossed from its start to `end_ns`, in
/// order, sampled every millisecond. Empty before the platform started.
std::vector<Crossing> crossings(const Platform& truth, const graph::Graph& g, std::int64_t end_ns);

/// Each changeRoom against the platform: based on a pose inside the new room that the platform
/// really had. `exact`: also at the first or second pose past the crossing (`frame_ns`: the
/// navigation agent's frame period) and committed within `lag_ms` of that pose.
std::vector<std::string> room_change_failures(const graph::Graph& g, const Platform& truth,
                                              const std::vector<RoomChange>& changes, bool exact,
                                              double lag_ms, std::int64_t frame_ns);
/// changeRoom issued once per crossing in the platform's order (`exact`), or at least as often.
std::vector<std::string> crossing_count_failures(const std::vector<RoomChange>& changes,
                                                 const std::vector<Crossing>& expected, bool exact);

/// The fixed route's reach of the mug (kReach, kNoReach events): set at least once, each time
/// below `reach_on_m` by FCL and by the true distance from the platform's pose (within 1 cm),
/// never back to noReach (hysteresis). `once`: set exactly once.
std::vector<std::string> reach_failures(const std::vector<GraspEvent>& events,
                                        const Platform& truth, double reach_on_m, bool once);

/// Never grasping while the platform drives: a grasp completes (kGrasped, its run from the last
/// kStarted of the object) only if the platform drove during it for at most `allowance_ns`; an
/// object is put down (kReleased) only when the platform has not moved for `moved_window_ns`
/// less the allowance.
std::vector<std::string> grasp_motion_failures(const std::vector<GraspEvent>& events,
                                               const Platform& truth, std::int64_t allowance_ns,
                                               std::int64_t moved_window_ns);

/// Clean the table: each mug grasped and released (`once_each`: exactly once), never two objects
/// carried at once (kGrasped, kReleased events in order).
std::vector<std::string> carry_failures(const std::vector<GraspEvent>& events, bool once_each);

/// Clean the table: the first plan the planner agent wrote (`plans` by version) replays through
/// the grammar guard from the world (verify_clean_table_plan()) and is version 1. `verified` is
/// set to "ok" or why not when there is a plan (left as it is when there is none).
std::vector<std::string> first_plan_failures(const std::map<std::int64_t, std::string>& plans,
                                             std::string& verified);

}  // namespace quiver::agents::inline apps::agm
