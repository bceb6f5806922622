#pragma once
/// @file
/// The team scenario (docs/teams.md, issue 23) in the simulator: seed 001's clean-the-table world
/// with R robots (team_world.h), each robot its own network with its agents and a gateway (two
/// replicas and a bridge, as `quiver gateway` runs them), the team network slower and lossier.
/// Every robot runs navigation, rooms, grasping and a planner for itself; robot A also tracks the
/// two people (2 x 15 joints at `humans_hz`); more agents per robot are idle. No executive: the
/// robots' planners race for the mugs, their grasps compete through priority locks held across
/// robots and the grammar, and the hand (SharedCustody) holds a mug for one robot at most.
///
/// Checked over time: no mug is ever carried by two robots on any replica; no grasp starts while
/// its robot's platform moves, and none completes unless it stood still through it (allowing
/// 500 ms for a pose in flight). At the end (every fault healed, every process back, the tracker
/// stopped, 5 s of quiet): every mug in the kitchen, on nothing and carried by no one, and let go
/// by every hand; every robot's plan achieved; the joints reached every robot; every replica of
/// every robot equal (agents and both sides of every gateway). A failing run prints its replay
/// command.
#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "quiver/sim/fault_model.h"
#include "quiver/sim/scenario_app.h"
#include "quiver/sim/scenario_run.h"

namespace quiver::agents::inline apps::agm {

/// The team app as the simulator runs it (built once).
const sim::ScenarioApp& team_app();

struct TeamScenario {
  std::string name = "agm-team";
  int robots = 2;
  /// Processes per robot, its gateway included: navigation, rooms, grasping, planner, the human
  /// tracker on robot A (an idle agent on the others), then idle agents. At least 6.
  int agents_per_robot = 6;
  double humans_hz = 30;
  /// The team network's loss from the start (faults may change it; `heal` clears it).
  double team_loss = 0;
  /// Names: robots ("A": all its processes at once), gateways ("A-gateway"), agents
  /// ("A-grasping"). A partition naming robots cuts the team network between them; loss applies
  /// to the team network only.
  std::vector<sim::FaultEvent> faults;
  double limit_s = 150;
  /// A control: false runs the grasps without their lock on the object and without the hand's
  /// custody (only the grammar guards them), so that robots cut off from each other both take one
  /// mug: the checks must then fail.
  bool guards = true;

  /// Random faults from `seed`: loss on the team network up to 20%, one to two cuts of the team
  /// link (robots split in two groups) lasting 2 to 10 s, up to two crashes of a whole robot or
  /// of a gateway (restarted 0.5 to 3 s later, empty), all in the first 30 s.
  static TeamScenario random_faults(std::uint64_t seed, int robots, int agents_per_robot);
  /// The robots' agent names, robot by robot.
  std::vector<std::string> agent_names() const;
};

/// A run's outcome: whether every check held, what failed, and its figures (converged,
/// fetched_by, grasps, misses, replans, team_bytes, heal_converge_ms, joints_seen, ...).
using TeamResult = sim::ScenarioOutcome;

TeamResult run_team_scenario(const TeamScenario& s, std::uint64_t seed,
                             std::function<void(std::int64_t t_ns, const std::string&)> log = {});

}  // namespace quiver::agents::inline apps::agm
