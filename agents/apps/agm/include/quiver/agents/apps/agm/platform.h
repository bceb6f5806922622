#pragma once
/// @file
/// The simulated mobile platform the navigation agent commands (the device behind it, as the
/// Barthel agents have simulated speech and screens). It follows a route of legs — drive to a
/// point at a speed, stand still for a while, or wait until released (the navigation agent
/// releases it once the grasp is done) — from the time it is started. Its odometry is the truth
/// the scenario checks against: where the robot is at any time and when it moved.
///
/// Times are the agents' clock (virtual in the simulator, CLOCK_MONOTONIC in processes). Not
/// thread-safe: the navigation agent's thread (or the simulator's) owns it.
#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

namespace quiver::agents::inline apps::agm {

struct Pose2 {
  double x = 0, y = 0, yaw = 0;
};

struct Leg {
  enum class Kind : std::uint8_t { kDrive, kStand, kWait } kind = Kind::kStand;
  double x = 0, y = 0;  ///< kDrive: the goal
  double speed = 0.5;   ///< kDrive: metres per second (> 0)
  double seconds = 0;   ///< kStand: how long; kWait: the longest it waits (then it goes on)
};

/// The route of the AGM scenario: from the kitchen through the corridor to the table in the
/// living room, a stop short of it, the approach into reach, a nudge back and forth in the middle
/// of the grasp, a wait until the mug is carried, and the way back to the kitchen.
std::vector<Leg> default_route();
/// The robot's start: the robot's pose in the scenario's world.
Pose2 default_start();

class Platform {
 public:
  Platform(std::vector<Leg> route, Pose2 start);

  /// Before start(): the robot stands at `p` instead (a navigation process restarted mid-task
  /// starts where its localization, the graph, puts the robot). Ignored once started.
  void relocate(Pose2 p) {
    if (!t0_) start_ = p;
  }
  /// Starts the route at `t0` (once; later calls are ignored).
  void start(std::int64_t t0);
  bool started() const { return t0_.has_value(); }
  std::int64_t t0() const { return t0_.value_or(0); }
  /// Appends a drive to (x, y) at `speed` m/s, from `t` or when the legs before it end (standing
  /// still until then): a navigation agent that follows a plan adds its legs as the plan asks.
  /// Starts the platform at `t` if it was not started.
  void go_to(std::int64_t t, double x, double y, double speed);
  /// Ends the current wait leg at `t` (ignored unless waiting at `t`). @returns whether it did.
  bool release(std::int64_t t);
  std::optional<std::int64_t> released_at() const { return release_; }

  /// Where the odometry puts the robot at `t` (the start pose before start()).
  Pose2 pose(std::int64_t t) const;
  /// Whether the platform drives at `t`.
  bool moving(std::int64_t t) const;
  /// Whether it drove at any time in (a, b].
  bool moved_between(std::int64_t a, std::int64_t b) const;
  /// Whether it waits to be released at `t`.
  bool waiting(std::int64_t t) const;
  /// Whether every leg is done at `t`.
  bool finished(std::int64_t t) const;
  /// The drives as [begin, end] times (after an unreleased wait: as if it timed out).
  std::vector<std::pair<std::int64_t, std::int64_t>> drives() const;
  /// When the last leg ends (an unreleased wait counted to its timeout), or nullopt before
  /// start().
  std::optional<std::int64_t> end_time() const;

 private:
  struct Span {
    std::int64_t begin = 0, end = 0;
    Pose2 from, to;
    Leg::Kind kind = Leg::Kind::kStand;
  };
  std::vector<Span> spans() const;

  std::vector<Leg> route_;
  Pose2 start_;
  std::optional<std::int64_t> t0_, release_;
};

}  // namespace quiver::agents::inline apps::agm
