// Eigen views of the graph's poses: a pose X_PC to and from an Eigen isometry, and RT edges read and set with one.
#include "quiver/kinematics/eigen_pose.h"

#include <cmath>

namespace quiver::kinematics {

Eigen::Quaterniond rotation(const graph::Pose& X_PC) {
  const auto& r = X_PC.rotation;
  Eigen::Quaterniond q(r[0], r[1], r[2], r[3]);
  const double n = q.norm();
  if (!(n > 0.0) || !std::isfinite(n)) return Eigen::Quaterniond::Identity();
  q.coeffs() /= n;
  return q;
}

Eigen::Matrix3d rotation_matrix(const graph::Pose& X_PC) { return rotation(X_PC).toRotationMatrix(); }

Eigen::Vector3d translation(const graph::Pose& X_PC) {
  return {X_PC.translation[0], X_PC.translation[1], X_PC.translation[2]};
}

Eigen::Isometry3d to_isometry(const graph::Pose& X_PC) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = rotation_matrix(X_PC);
  X.translation() = translation(X_PC);
  return X;
}

graph::Pose to_pose(const Eigen::Isometry3d& X_PC) {
  Eigen::Quaterniond q(X_PC.linear());
  q.normalize();
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();  // one of the two quaternions of a rotation
  graph::Pose p;
  p.translation = {X_PC.translation().x(), X_PC.translation().y(), X_PC.translation().z()};
  p.rotation = {q.w(), q.x(), q.y(), q.z()};
  return p;
}

std::optional<Eigen::Isometry3d> rt_transform(const graph::Graph& g, graph::NodeId child) {
  auto e = g.rt_edge(child);
  if (!e) return std::nullopt;
  return to_isometry(e->pose);
}

Status set_rt(graph::Transaction& tx, graph::NodeId parent, graph::NodeId child, const Eigen::Isometry3d& X_PC,
              std::int64_t stamp) {
  return tx.set_rt(parent, child, to_pose(X_PC), stamp);
}

}  // namespace quiver::kinematics
