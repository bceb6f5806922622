#pragma once
/// @file
/// The navigation agent (AGM, seed 001, III-A): it drives the platform along its route and, at
/// `rate_hz`, publishes the robot's pose from localization as the RT edge world -> robot (with a
/// little localization jitter, as a real one has even when the robot stands still). From the
/// platform's odometry — not from the jittery pose — it keeps the unary predicate
/// movedInLastSeconds (the self-loop robot -> robot) set while the platform moved in the last
/// `moved_window_ns`, and cleared after. When the platform waits for the grasp and the graph says
/// the robot carries an object, it releases the platform. Grammar: grammars/navigation.aggl.
#include <cstdint>
#include <functional>
#include <memory>

#include "quiver/agents/apps/agm/agm_schema.h"
#include "quiver/agents/apps/agm/latency_probe.h"
#include "quiver/agents/apps/agm/platform.h"
#include "quiver/agents/runtime/api/agent.h"

namespace quiver::agents::inline apps::agm {

struct NavigationOptions {
  /// Which robot's nodes it works on (a team: RobotNames::of(tag)).
  RobotNames names;
  double rate_hz = 30;
  std::int64_t moved_window_ns = 1'000'000'000;
  double jitter_m = 0.003;  ///< localization noise (uniform, each axis)
  /// Stop publishing once the route is done and the predicate cleared (the robot is parked and
  /// its localization off): lets replicas go quiet at the end of a scenario.
  bool quiet_when_done = false;
  bool measure_humans = false;  ///< a LatencyProbe on the human joints (status: humans_latency)
  /// Clean the table: no fixed route; whenever the platform stands idle it drives where the plan
  /// node's next step asks (changeRoom: to the waypoint of room `b`; approach: in front of
  /// object `o`, `approach_offset_m` short of it along x, at `approach_speed`). Done (for
  /// quiet_when_done) once the plan is achieved.
  bool follow_plan = false;
  /// A team's process (docs/teams.md): a platform not yet started begins where the graph puts the
  /// robot (a restart mid-task), and each drive the plan asks for is reported (begin, end: the
  /// agents' clock) for the scenario's checks.
  bool resume_from_graph = false;
  std::function<void(std::int64_t begin_ns, std::int64_t end_ns)> on_drive;
  double speed = 1.0, approach_speed = 0.25, approach_offset_m = 0.45;
};

class Navigation final : public Agent {
 public:
  /// `platform` may be shared with whoever checks it (the simulator keeps it across restarts).
  Navigation(std::shared_ptr<Platform> platform, NavigationOptions o = {},
             std::string name = "navigation");
  void setup(AgentContext& ctx) override;
  void status(nlohmann::json& out) const override;

  const Platform& platform() const { return *platform_; }
  const LatencyProbe& probe() const { return probe_; }

 private:
  void frame(AgentContext& ctx);
  void steer(const graph::Graph& g, std::int64_t now);
  std::shared_ptr<Platform> platform_;
  NavigationOptions opt_;
  LatencyProbe probe_;
  std::uint64_t frames_ = 0, refused_ = 0, moved_set_ = 0, moved_cleared_ = 0, goals_ = 0;
};

}  // namespace quiver::agents::inline apps::agm
