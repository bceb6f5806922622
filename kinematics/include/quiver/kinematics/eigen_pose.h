#pragma once
/// @file
/// Eigen views of the graph's poses. The graph stores a pose X_PC as a translation p_PoCo_P and a
/// unit quaternion R_PC = (w, x, y, z) and knows nothing of Eigen (graph/ sits below
/// kinematics/); these conversions are the one place the two meet. The same X_AB naming as
/// frames.h: X_PC is the pose of child frame C in parent frame P.

#include <cstdint>
#include <optional>

#include <Eigen/Geometry>

#include "quiver/graph/graph.h"
#include "quiver/base/result.h"

namespace quiver::kinematics {

/// X_PC as an Eigen isometry. A quaternion that is not unit length is normalised first; a zero or
/// non-finite one reads as the identity rotation (as the frame tree reads it).
Eigen::Isometry3d to_isometry(const graph::Pose& X_PC);
/// An isometry as a graph pose (its rotation part re-orthonormalised through a quaternion with
/// w >= 0).
graph::Pose to_pose(const Eigen::Isometry3d& X_PC);

/// p_PoCo_P: the translation of a pose.
Eigen::Vector3d translation(const graph::Pose& X_PC);
/// R_PC as a (normalised) quaternion.
Eigen::Quaterniond rotation(const graph::Pose& X_PC);
/// R_PC as a 3x3 rotation matrix.
Eigen::Matrix3d rotation_matrix(const graph::Pose& X_PC);

/// X_PC of `child`'s current RT edge (P its RT parent), or nullopt if it has none.
std::optional<Eigen::Isometry3d> rt_transform(const graph::Graph& g, graph::NodeId child);
/// Transaction::set_rt() with an Eigen isometry: puts `child` under `parent` with X_PC at `stamp`.
/// @returns the errors of Transaction::set_rt().
Status set_rt(graph::Transaction& tx, graph::NodeId parent, graph::NodeId child, const Eigen::Isometry3d& X_PC,
              std::int64_t stamp = 0);

}  // namespace quiver::kinematics
