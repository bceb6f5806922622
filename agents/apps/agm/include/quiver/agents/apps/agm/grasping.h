#pragma once
/// @file
/// The grasping agent (AGM, seed 001, III-B). Reach: at `rate_hz` it measures, with the FCL scene
/// of its own replica (kinematics/collision_scene.h), the distance between the gripper and every
/// object the robot has a reach or noReach edge to, and turns noReach into reach below
/// `reach_on_m` and reach into noReach above `reach_off_m` (hysteresis: localization jitter near
/// one threshold does not make the edges flicker). The new edge records `distance` and the
/// `stamp_ns` of the robot pose it was computed from.
///
/// Grasp: an action (agents/runtime) for each object the robot is to fetch and reaches. It needs
/// the platform still — no movedInLastSeconds on the robot — and a fresh robot pose (one stamped
/// within `fresh_ns`: an agent cut off from the navigation agent cannot know the robot stands
/// still). It announces robot -[grasping]-> object while it runs; when the platform moves (or the
/// pose goes stale) it is paused: the mark goes, and it starts again once the robot is still.
/// After `grasp_ns` of uninterrupted grasping the object is carried: its RT edge moves under the
/// gripper. Grammar: grammars/grasping.aggl.
///
/// In a team (docs/teams.md) robots reach for the same objects: the grasp then holds a priority
/// lock on the object (`lock_objects`, across robots through the gateways), and the hand closes
/// through the Custody device, which lets only one robot hold an object (a robot cut off from the
/// others by a partition finds the object gone, as a real gripper would).
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "quiver/agents/apps/agm/agm_schema.h"
#include "quiver/agents/apps/agm/custody.h"
#include "quiver/agents/apps/agm/latency_probe.h"
#include "quiver/agents/runtime/api/agent.h"

namespace quiver::kinematics {
class FrameTree;
class CollisionScene;
}  // namespace quiver::kinematics

namespace quiver::agents::inline apps::agm {

/// What the grasping agent did, for checks and traces.
struct GraspEvent {
  enum class Kind : std::uint8_t {
    kReach,
    kNoReach,
    kStarted,
    kPaused,
    kGrasped,
    kReleased,  ///< clean the table: put down in the robot's room
    kMissed     ///< the hand closed on nothing: another robot holds the object (Custody)
  } kind = Kind::kReach;
  std::string object;
  std::int64_t t_ns = 0;
  double distance = 0;        ///< kReach, kNoReach: the FCL distance gripper-object
  std::int64_t stamp_ns = 0;  ///< kReach, kNoReach: the robot pose's stamp it came from
  const char* name() const;
};

struct GraspingOptions {
  /// Which robot's nodes it works on (a team: RobotNames::of(tag)).
  RobotNames names;
  double rate_hz = 15;
  double reach_on_m = 0.10;
  double reach_off_m = 0.15;
  std::int64_t grasp_ns = 1'500'000'000;
  std::int64_t fresh_ns = 300'000'000;
  bool measure_humans = false;
  /// Clean the table: also grasp the object the plan node's next step `grasp` names (no fetch
  /// edge needed; it comes off the table: graspFromTable), and put down the carried object when
  /// the next step is `release` and the robot stands still (its RT edge moves under the world,
  /// where the gripper is).
  bool follow_plan = false;
  std::function<void(const GraspEvent&)> on_event;
  /// A team: hold a priority lock on the object while grasping it, and close the hand through
  /// `custody` (null: the hand always closes). After a miss the object is left alone for
  /// `retry_ns`.
  bool lock_objects = false;
  std::shared_ptr<Custody> custody;
  std::int64_t retry_ns = 1'000'000'000;
};

class Grasping final : public Agent {
 public:
  explicit Grasping(GraspingOptions o = {}, std::string name = "grasping");
  ~Grasping() override;
  void setup(AgentContext& ctx) override;
  /// Drops the FCL scene and the frame tree (they follow the replica, which the host destroys
  /// after the agent stops).
  void teardown(AgentContext& ctx) override;
  void status(nlohmann::json& out) const override;

  /// Whether the robot may grasp now, from this replica: it is not moving and its pose is fresh.
  bool platform_still(AgentContext& ctx) const;
  void note(const GraspEvent& e);
  const GraspingOptions& options() const { return opt_; }
  /// A control for tests: grasp without the lock on the object (GraspingOptions::lock_objects).
  void drop_object_locks() { opt_.lock_objects = false; }
  const LatencyProbe& probe() const { return probe_; }

 private:
  void measure(AgentContext& ctx);
  void release(AgentContext& ctx);
  GraspingOptions opt_;
  std::unique_ptr<kinematics::FrameTree> frames_;
  std::unique_ptr<kinematics::CollisionScene> scene_;
  LatencyProbe probe_;
  std::uint64_t reach_changes_ = 0, grasps_ = 0, pauses_ = 0, refused_ = 0, releases_ = 0;
};

}  // namespace quiver::agents::inline apps::agm
