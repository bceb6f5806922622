#pragma once
/// @file
/// The AGM scenarios of seed 001 in the simulator: the app's registration with it (agm_app(): the
/// navigation, rooms, grasping and human-tracking agents of agents/apps/agm, the planner agent and
/// the 'person' of clean-table, on the AGM world; its settings, checks, shared devices, when a run
/// is done and how it settles), and the typed scenario that tests and `quiver sim --agm` use. A
/// scenario file is the simulator's (sim/scenario.h: faults are sim/fault_model.h's partitions,
/// packet loss, kill -9 and restart of any agent) with the AGM keys "humans", "humans_hz",
/// "reach_off_m", "mission", "put_back_s". What must hold — over time and at the end (the checks
/// themselves: agents/apps/agm/agm_checks.h, shared with the processes over DDS):
///  - the robot ends in the kitchen, carrying the mug, which is in the kitchen too;
///  - changeRoom follows the platform: every change is based on a real pose inside the new room;
///    without faults, exactly one change per crossing, issued at the first or second pose past it,
///    committed within `crossing_lag_ms` of that pose;
///  - reach only when the FCL distance (and an independent closed-form distance from the
///    platform's true pose) is below the threshold; never back to noReach (hysteresis);
///  - never grasping while the platform moves: a running grasp is paused within
///    `motion_allowance_ms` of the platform starting to move, and a grasp completes only if the
///    platform stood still through it; without faults, the nudge mid-grasp pauses it;
///  - movedInLastSeconds on the navigation agent's replica matches the odometry;
///  - after healing, every replica equal (digests).
///
/// The checks by name in a scenario file ("checks": {name: parameter}): finished, converged,
/// end_state, moved_matches_odometry, no_grasp_while_driving, reach, grasps, room_changes,
/// human_poses_delivered, plan, expect_pause (true or false each: on or off), and the parameters
/// exact_crossings (true or false), crossing_lag_ms and motion_allowance_ms (milliseconds) of
/// room_changes, grasps and no_grasp_while_driving. The typed scenario runs them all.
#include <cstdint>
#include <functional>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "quiver/base/result.h"
#include "quiver/sim/fault_model.h"
#include "quiver/sim/scenario_app.h"

namespace quiver::agents::inline apps::agm {

/// The AGM app as the simulator runs it (built once).
const sim::ScenarioApp& agm_app();

struct AgmChecks {
  bool exact_crossings = true;
  double crossing_lag_ms = 60;
  bool expect_pause = true;
  double motion_allowance_ms = 100;
};

struct AgmScenario {
  std::string name = "agm";
  std::vector<sim::FaultEvent> faults;  ///< agents: navigation, rooms, grasping, humans
  AgmChecks checks;
  bool humans = true;
  double humans_hz = 30;
  double limit_s = 150;
  /// The grasping agent's threshold back to noReach (its reach threshold is 0.10 m); equal to
  /// that, there is no hysteresis (a control: the nudge then makes reach flicker).
  double reach_off_m = 0.15;
  /// "" (the fixed route: fetch the mug) or "clean-table" (agents/apps/agm/clean_table.h: the planner
  /// agent runs too, plans from the world, and navigation and grasping follow its plan's next
  /// step: both mugs from the table to the kitchen, one at a time). Checked: the mission holds
  /// on the final replica, the plan is achieved, the first plan replays through the grammar
  /// guard, replicas equal, each mug grasped and released while the platform stood still,
  /// changeRoom per crossing (exact without faults).
  std::string mission;
  /// clean-table: at this time (s; 0: never) a person puts the first mug back on the table if it
  /// is not carried (a sixth agent, "person", with its own grammar: rule putBack): the world
  /// deviates from the plan and the planner must plan again. Checked: at least one replan, and
  /// the mission still reached.
  double put_back_s = 0;
  /// From a scenario file (docs/scenarios.md): {"name", "faults": [...] naming the agents the
  /// mission runs, "checks": {"exact_crossings", "crossing_lag_ms", "expect_pause",
  /// "motion_allowance_ms", ...}, "humans", "humans_hz", "reach_off_m", "limit_s" (>= 45),
  /// "mission", "put_back_s"}; its agents and world follow from the mission.
  /// @returns kInvalidArgument naming `source` and the JSON pointer of a bad value.
  static Result<AgmScenario> parse(const nlohmann::json& j, const std::string& source);
  static Result<AgmScenario> load(const std::string& path);
  /// Random faults drawn from `seed` (loss up to 20%, up to two partitions and two kill -9 and
  /// restarts of any agent, all in the first 35 s), with the checks that still hold under them.
  static AgmScenario random_faults(std::uint64_t seed);
  /// The same draw for the clean-the-table mission (the planner among the agents killed).
  static AgmScenario random_faults(std::uint64_t seed, const std::string& mission);
};

struct AgmResult {
  std::string name;
  std::uint64_t seed = 0;
  bool passed = false;
  std::vector<std::string> failures;
  bool converged = false;
  std::string final_room;
  int room_changes = 0, expected_room_changes = 0;
  int reach_changes = 0, pauses = 0, grasps = 0;
  double grasped_s = -1;   ///< virtual time the mug was carried
  double finished_s = -1;  ///< virtual time the route ended
  int kills = 0, partitions = 0;
  std::uint64_t rejected = 0;
  std::uint64_t human_deliveries = 0;  ///< joint poses the surviving probes saw
  double human_latency_p99_ms = 0;     ///< virtual one-way latency, humans -> every other agent
  // clean-table:
  bool mission_holds = false;
  std::string plan_status, plan_verified;
  int plan_steps = 0, releases = 0;
  std::int64_t plan_version = 0, replans = 0;
  nlohmann::json to_json() const;
};

/// The clean-the-table run (what run_agm_scenario() does when s.mission is "clean-table").
AgmResult run_agm_clean_table(const AgmScenario& s, std::uint64_t seed,
                              std::function<void(std::int64_t t_ns, const std::string&)> log = {});

AgmResult run_agm_scenario(const AgmScenario& s, std::uint64_t seed,
                           std::function<void(std::int64_t t_ns, const std::string&)> log = {});

}  // namespace quiver::agents::inline apps::agm
