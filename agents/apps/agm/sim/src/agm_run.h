#pragma once
// What the agents and checks of one AGM run share (the app's state in sim::ScenarioRun::state()):
// the devices and records that outlive an agent's incarnation, what settle() measured, and the
// AGM keys of a scenario file (settings and check parameters) read into the typed scenario.
#include <cstdint>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "quiver/agents/apps/agm/agm_checks.h"
#include "quiver/agents/apps/agm/agm_roles.h"
#include "quiver/agents/apps/agm/agm_schema.h"
#include "quiver/agents/apps/agm/sim/agm_scenario.h"
#include "quiver/sim/scenario_run.h"

namespace quiver::agents::inline apps::agm::internal {

struct AgmRun {
  AgmScenario spec;  ///< the run's settings and check parameters (its name and faults unused)
  /// The platform (the robot keeps driving when its navigation agent dies) and what the agents
  /// reported doing, across their incarnations.
  std::shared_ptr<Platform> platform;
  AgmRoleOptions roles;
  std::vector<RoomChange> changes;
  std::vector<GraspEvent> grasps;
  std::map<int, std::int64_t> started_at;     ///< agent index -> its incarnation's setup time
  std::map<std::int64_t, std::string> plans;  ///< clean-table: the plans by version, as written
  std::int64_t achieved_at = -1;              ///< clean-table: since when the plan is achieved
  // What settle() found: whether the route (the plan) was done when the run ended...
  bool finished = false;
  double finished_s = -1;
  // ...what the surviving probes saw, and the facts of the settled replicas.
  std::uint64_t human_deliveries = 0;
  double human_latency_p99_ms = 0;
  bool converged = false;
  std::vector<Crossing> expected;          ///< the platform's crossings of room limits
  std::vector<std::string> plan_failures;  ///< clean-table: first_plan_failures()
  std::string plan_verified;
  int plan_steps = 0;

  bool clean_table() const { return spec.mission == kCleanTable; }
};

AgmRun& agm_run(sim::ScenarioRun& run);
/// The replica the final checks read (the first agent's, once settled).
const graph::Graph& final_replica(sim::ScenarioRun& run);

/// The AGM keys of a scenario file into `s` ("humans", "humans_hz", "reach_off_m", "mission",
/// "put_back_s"); any other is unknown. @returns kInvalidArgument naming `source` and the pointer.
Status read_settings(const nlohmann::json& keys, const std::string& source, AgmScenario& s);
nlohmann::json write_settings(const AgmScenario& s);
/// The check parameters of a scenario's (validated) "checks" into `c`.
void read_check_params(const nlohmann::json& checks, AgmChecks& c);
/// The checks the typed scenario runs: all of them, with its parameters.
nlohmann::json write_checks(const AgmChecks& c);

/// Registers the AGM checks by name (agm_sim_checks.cc).
void register_checks(sim::ScenarioApp& app);

}  // namespace quiver::agents::inline apps::agm::internal
