#pragma once
// Private: poses in the source formats' convention — a translation in millimetres and Euler
// angles (rx, ry, rz) in radians with R = Rx(rx)·Ry(ry)·Rz(rz), the composition RoboComp's RTMat
// and CORTEX's RT_API build — to and from Quiver's (metres, unit quaternion [w, x, y, z]).
// This is not the URDF roll-pitch-yaw of world files (R = Rz·Ry·Rx): a separate convention.

#include <array>

#include "quiver/graph/ids.h"

namespace quiver::interop::internal {

/// X_PC from t (in units of `metres_per_unit` metres: 0.001 for mm) and (rx, ry, rz) (rad).
graph::Pose pose_from_xyz(const std::array<double, 3>& t, const std::array<double, 3>& r, double metres_per_unit);

/// The inverse of pose_from_xyz(): t in units of `metres_per_unit`; ry in [-π/2, π/2], rx and rz in [-π, π]; at
/// ry = ±π/2 (gimbal lock) rx is 0.
void xyz_from_pose(const graph::Pose& X, double metres_per_unit, std::array<double, 3>& t, std::array<double, 3>& r);

}  // namespace quiver::interop::internal
