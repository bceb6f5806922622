#pragma once
/// @file
/// The robot-in-room agent (AGM, seed 001, III-A, Fig. 2b): on every change of the robot's pose
/// (the RT edge world -> robot) it checks the pose against the limits of the robot's room; when
/// the pose has left that room for another, it issues changeRoom — moves the symbolic edge
/// robot -[in]-> room, and the `in` edges of the objects the robot carries — one rule application
/// per room along the transitable path (one step when it saw the crossing itself). The new `in`
/// edge records what the change was based on: x, y and stamp_ns of the pose, committed_ns.
/// Grammar: grammars/rooms.aggl (its constraint robotInOneRoom is repaired by this agent).
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "quiver/agents/apps/agm/agm_schema.h"
#include "quiver/agents/apps/agm/latency_probe.h"
#include "quiver/agents/runtime/api/agent.h"

namespace quiver::agents::inline apps::agm {

/// One changeRoom this agent committed.
struct RoomChange {
  std::string from, to;
  double x = 0, y = 0;        ///< the robot's position it reacted to
  std::int64_t stamp_ns = 0;  ///< that pose's stamp
  std::int64_t committed_ns = 0;
};

struct RoomsOptions {
  /// Which robot's nodes it works on (a team: RobotNames::of(tag)).
  RobotNames names;
  bool measure_humans = false;
  /// Told of every committed change (the simulator's checks keep them across restarts).
  std::function<void(const RoomChange&)> on_change;
};

class Rooms final : public Agent {
 public:
  explicit Rooms(RoomsOptions o = {}, std::string name = "rooms");
  void setup(AgentContext& ctx) override;
  void status(nlohmann::json& out) const override;
  const std::vector<RoomChange>& changes() const { return changes_; }
  const LatencyProbe& probe() const { return probe_; }

 private:
  void check(AgentContext& ctx);
  RoomsOptions opt_;
  LatencyProbe probe_;
  std::vector<RoomChange> changes_;
  std::uint64_t refused_ = 0, outside_ = 0;
};

}  // namespace quiver::agents::inline apps::agm
