#pragma once
/// @file
/// The clean-the-table mission (AGM paper, seed 001, section IV) on the AGM scenario: the checks
/// the simulator and `quiver scenario agm --mission clean-table` make on a final replica, and
/// the replay of a plan the planner agent wrote through the grammar guard.
#include <cstdint>
#include <string>
#include <vector>

#include "quiver/graph/graph.h"
#include "quiver/base/result.h"

namespace quiver::agents::inline apps::agm {

struct CleanTableReport {
  bool mission_holds = false;
  std::vector<std::string> missing;  ///< what check_mission() reports missing
  std::string plan_status;           ///< the plan node's `status`
  std::string steps;                 ///< its `steps`
  std::int64_t version = 0, replans = 0, next = 0;
};

/// The mission (embedded clean-table.aggt, types from clean_table.aggl) checked on `g`, and the
/// plan node as the planner agent left it.
CleanTableReport check_clean_table(const graph::Graph& g);

/// Replays `steps` (one `rule@{...}` per line, as the plan node holds them) on a fresh graph
/// seeded with the clean-the-table world, through the grammar guard of the domain: each step must
/// be accepted as one application of its rule and leave the graph as the domain predicts, and
/// the mission must hold at the end. @returns kRefused (or the parse error) naming what failed.
Status verify_clean_table_plan(const std::string& steps);

}  // namespace quiver::agents::inline apps::agm
