#pragma once
/// @file
/// An FCL 0.7 collision scene that follows the graph: every node with a collision shape
/// (quiver/kinematics/shape.h) is an FCL object posed at X_RN, its pose in the root frame of its
/// RT tree. The scene listens to its FrameTree: when frames move, only their objects get a new
/// transform and AABB, and the broad phase (a dynamic AABB tree) updates only those leaves —
/// O(log n) per moved object, never a rebuild. Shape attribute changes rebuild that object alone.
///
/// Queries between objects of different RT trees fail with kNotConnected (they have no common
/// frame). Threading: like the FrameTree's owner API, a scene lives on the graph's owner thread.

#include <Eigen/Geometry>
#include <memory>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "quiver/kinematics/frames.h"
#include "quiver/kinematics/shape.h"

namespace quiver::kinematics {

/// collide(A, B).
struct CollisionInfo {
  bool in_collision = false;
  double penetration_depth = 0.0;  ///< of the deepest contact (0 when not in collision)
  Eigen::Vector3d p_AoC_A = Eigen::Vector3d::Zero();  ///< that contact's point, in frame A
  Eigen::Vector3d n_A = Eigen::Vector3d::Zero();      ///< its normal (from A towards B), in frame A
};

/// distance(A, B).
struct DistanceInfo {
  /// Shortest distance between the two shapes; 0 when they touch or overlap (see
  /// `in_collision`).
  double distance = 0.0;
  bool in_collision = false;
  Eigen::Vector3d p_AoPa_A = Eigen::Vector3d::Zero();  ///< nearest point on A, in frame A
  Eigen::Vector3d p_AoPb_A = Eigen::Vector3d::Zero();  ///< nearest point on B, in frame A
};

/// within_reach(target, base, reach).
struct ReachInfo {
  bool reachable = false;
  /// Distance from the base frame's origin to the nearest point of the target (its shape, or its
  /// origin when it has none); 0 when the origin is inside the shape.
  double distance = 0.0;
  Eigen::Vector3d p_BoN_B = Eigen::Vector3d::Zero();  ///< that nearest point N, in the base frame
};

class CollisionScene {
 public:
  /// Builds the scene from every shaped node of `frames`' graph and follows its updates.
  explicit CollisionScene(FrameTree& frames);
  ~CollisionScene();
  CollisionScene(const CollisionScene&) = delete;
  CollisionScene& operator=(const CollisionScene&) = delete;

  /// Whether the shapes of A and B intersect.
  /// @returns kNotFound (unknown frame), kInvalidArgument (no shape, or an invalid one, named),
  /// kNotConnected (different RT trees).
  Result<CollisionInfo> collide(FrameRef A, FrameRef B);
  /// Shortest distance between the shapes of A and B with the nearest points.
  Result<DistanceInfo> distance(FrameRef A, FrameRef B);
  /// Every pair of shaped nodes in contact (same RT tree), each pair once, ordered by node id.
  std::vector<std::pair<graph::NodeId, graph::NodeId>> colliding_pairs();
  /// Is `target` within `reach` metres of the origin of frame `base` (e.g. an arm's shoulder)?
  /// The grasping test of AGM's reach / noReach edges.
  /// @returns kInvalidArgument for a negative reach or an invalid target shape, kNotFound,
  /// kNotConnected.
  Result<ReachInfo> within_reach(FrameRef target, FrameRef base, double reach);

  std::size_t object_count() const;
  /// Shaped nodes whose shape could not be built, with the reason (bad attributes, mesh file).
  std::vector<std::pair<graph::NodeId, std::string>> problems() const;

  struct Stats {
    std::size_t objects = 0;
    std::uint64_t objects_updated = 0;     ///< transform + AABB refreshes of moved objects
    std::uint64_t shapes_built = 0;        ///< geometries (re)built from attributes
    std::uint64_t broadphase_updates = 0;  ///< incremental broad-phase update calls
    std::uint64_t full_rebuilds = 0;       ///< scene rebuilt from scratch (construction, resync)
  };
  Stats stats() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace quiver::kinematics
