// Eigen views of graph poses (eigen_pose.h) and the frame tree's translation/rotation getters.

#include "quiver/kinematics/eigen_pose.h"

#include <gtest/gtest.h>

#include <cmath>

#include "quiver/kinematics/frames.h"

namespace quiver::kinematics {
namespace {

using graph::Graph;
using graph::NodeId;
using graph::Pose;

Eigen::Isometry3d make(double x, double y, double z, double angle, const Eigen::Vector3d& axis) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
  X.translation() = Eigen::Vector3d(x, y, z);
  return X;
}

TEST(EigenPose, RoundTrip) {
  const Eigen::Isometry3d X = make(1, -2, 3, 2.5, {1, 2, -0.5});
  const Pose p = to_pose(X);
  EXPECT_GE(p.rotation[0], 0.0);
  EXPECT_TRUE(to_isometry(p).isApprox(X, 1e-12));
  EXPECT_TRUE(translation(p).isApprox(Eigen::Vector3d(1, -2, 3)));
  EXPECT_TRUE(rotation_matrix(p).isApprox(X.linear(), 1e-12));
  EXPECT_TRUE(rotation(p).toRotationMatrix().isApprox(X.linear(), 1e-12));
  // A quaternion that is not unit length reads normalised; a zero one as the identity.
  Pose q;
  q.rotation = {2.0, 0.0, 0.0, 0.0};
  EXPECT_TRUE(rotation_matrix(q).isApprox(Eigen::Matrix3d::Identity()));
  q.rotation = {0.0, 0.0, 0.0, 0.0};
  EXPECT_TRUE(to_isometry(q).isApprox(Eigen::Isometry3d::Identity()));
  EXPECT_EQ(to_pose(Eigen::Isometry3d::Identity()), Pose::identity());
}

TEST(EigenPose, RtEdgesAndFrameGetters) {
  Graph g(graph::ReplicaId{7, 1});
  const Eigen::Isometry3d X_WR = make(1, 0, 0, M_PI / 2, {0, 0, 1});
  const Eigen::Isometry3d X_RC = make(0, 2, 0.5, 0.3, {1, 0, 0});
  NodeId world, robot, camera;
  {
    auto tx = g.begin();
    world = tx.create_node("world", "world").value();
    robot = tx.create_node("robot", "robot").value();
    camera = tx.create_node("camera", "camera").value();
    ASSERT_TRUE(set_rt(tx, world, robot, X_WR, 10).ok());
    ASSERT_TRUE(set_rt(tx, robot, camera, X_RC, 10).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  ASSERT_TRUE(rt_transform(g, robot).has_value());
  EXPECT_TRUE(rt_transform(g, robot)->isApprox(X_WR, 1e-12));
  EXPECT_FALSE(rt_transform(g, world).has_value());

  FrameTree tree(g);
  const Eigen::Isometry3d X_WC = X_WR * X_RC;
  auto p_WC = tree.translation("world", "camera");
  ASSERT_TRUE(p_WC.ok()) << p_WC.error().to_string();
  EXPECT_TRUE(p_WC->isApprox(X_WC.translation(), 1e-9));
  auto R_WC = tree.rotation("world", "camera");
  ASSERT_TRUE(R_WC.ok());
  EXPECT_TRUE(R_WC->isApprox(X_WC.linear(), 1e-9));
  auto reader = tree.reader();
  auto p_CW = reader.translation(camera, world);
  ASSERT_TRUE(p_CW.ok());
  EXPECT_TRUE(p_CW->isApprox(X_WC.inverse().translation(), 1e-9));
  auto bad = tree.translation("world", "nowhere");
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().code, ErrorCode::kNotFound);
}

}  // namespace
}  // namespace quiver::kinematics
