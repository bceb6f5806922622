// Translation onto Quiver of RoboComp CORTEX's DSR tests, file tests/graph/inner_gaussian.cpp
// (robocomp/cortex). Each TEST names the CORTEX TEST_CASE it keeps the intent of.
//
// CORTEX's InnerGaussianAPI propagates the covariance kept on RT edges (rt_covariance, 6x6 row-major
// floats) through chains of transforms and through point / pose transforms. Quiver keeps such a
// covariance as an RT edge attribute (stored on the child as rt:rt_covariance) but has no
// uncertainty propagation: the means are the FrameTree's transforms, the covariances are not
// computed anywhere. The two cases that also check means and stored covariances are translated as
// (b), asserting those; the four Monte Carlo cases check only the propagated covariance and are
// not translated (see the report).
//
// The graph is seeded from data/edge_world.json (CORTEX's make_edge_config_file(): root -> room ->
// Shadow). DSR's insert_or_assign_edge_RT(n, to, translation, euler_xyz, covariance, stamp) is
// set_rt() plus set_edge_attr(…, "rt_covariance", …) in one transaction.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <string>

#include <Eigen/Geometry>

#include "cortex_graph_fixture.h"
#include "quiver/kinematics/frames.h"

namespace quiver::cortex_tests {
namespace {

// A 6x6 diagonal covariance packed row-major into 36 floats (DSR's rt_covariance layout).
FloatVec diagonal_covariance(double tx, double ty, double tz, double rx, double ry, double rz) {
  FloatVec packed(36, 0.f);
  const double d[6] = {tx, ty, tz, rx, ry, rz};
  for (int i = 0; i < 6; ++i) packed[static_cast<std::size_t>(i * 6 + i)] = static_cast<float>(d[i]);
  return packed;
}

double yaw_of(const Eigen::Isometry3d& X) { return std::atan2(X.linear()(1, 0), X.linear()(0, 0)); }

class CortexInnerGaussian : public CortexWorldTest {
 protected:
  CortexInnerGaussian() : CortexWorldTest("edge_world.json", ReplicaId{0xC9, 1}) {}
  // DSR's insert_or_assign_edge_RT with a covariance.
  Status insert_rt_with_covariance(NodeId parent, NodeId child, const Eigen::Vector3d& t,
                                   const Eigen::Vector3d& rxyz, const FloatVec& covariance, std::int64_t stamp) {
    return insert_or_assign_rt(g, parent, child, t, rxyz, stamp, covariance);
  }
  // RT_API::get_covariance_matrix(parent, child): the stored 6x6, row-major.
  Result<FloatVec> covariance_of(NodeId parent, NodeId child) const {
    return g.get<FloatVec>(EdgeKey{parent, child, graph::symbols::rt()}, "rt_covariance");
  }
};

// CORTEX inner_gaussian.cpp, TEST_CASE "InnerGaussian propagates RT chain covariance". (b) The
// per-edge covariances read back (get_covariance_matrix) and the chain's mean (Shadow in root:
// x = -12) are asserted as in DSR; the chained covariance (0.25 + 0.75 = 1.0 along x) is not,
// because Quiver does not propagate covariances.
TEST_F(CortexInnerGaussian, InnerGaussianPropagatesRtChainCovariance) {
  ASSERT_TRUE(insert_rt_with_covariance(root, room, {10., 0., 0.}, {0., 0., 0.},
                                        diagonal_covariance(0.25, 0, 0, 0, 0, 0), 1000)
                  .ok());
  ASSERT_TRUE(insert_rt_with_covariance(room, shadow, {2., 0., 0.}, {0., 0., 0.},
                                        diagonal_covariance(0.75, 0, 0, 0, 0, 0), 1000)
                  .ok());

  auto root_room_covariance = covariance_of(root, room);
  ASSERT_TRUE(root_room_covariance.ok()) << root_room_covariance.error().to_string();
  ASSERT_EQ(root_room_covariance->size(), 36u);
  EXPECT_NEAR((*root_room_covariance)[0], 0.25, 1e-6);

  auto room_robot_covariance = covariance_of(room, shadow);
  ASSERT_TRUE(room_robot_covariance.ok()) << room_robot_covariance.error().to_string();
  ASSERT_EQ(room_robot_covariance->size(), 36u);
  EXPECT_NEAR((*room_robot_covariance)[0], 0.75, 1e-6);

  kinematics::FrameTree tree(g);
  auto transform = tree.lookup_at("Shadow", "root", 1000);
  ASSERT_TRUE(transform.ok()) << transform.error().to_string();
  EXPECT_NEAR(transform->translation().x(), -12.0, 1e-6);
  EXPECT_NEAR(transform->translation().y(), 0.0, 1e-6);
}

// CORTEX inner_gaussian.cpp, TEST_CASE "InnerGaussian transforms points and poses". (b) The
// transformed means of a point, a 2-D pose (x, y, yaw) and a 3-D pose from root into room (room at
// x = 4 in root) are asserted as in DSR, through FrameTree::transform_point / transform_pose; the
// growth of their covariances is not, because Quiver does not propagate covariances.
TEST_F(CortexInnerGaussian, InnerGaussianTransformsPointsAndPoses) {
  ASSERT_TRUE(insert_rt_with_covariance(root, room, {4., 0., 0.}, {0., 0., 0.},
                                        diagonal_covariance(0.5, 0.25, 0, 0, 0, 0.04), 1000)
                  .ok());
  kinematics::FrameTree tree(g);

  auto point = tree.transform_point("room", "root", Eigen::Vector3d(1.0, 2.0, 0.0), 1000);
  ASSERT_TRUE(point.ok()) << point.error().to_string();
  EXPECT_NEAR(point->x(), -3.0, 1e-6);
  EXPECT_NEAR(point->y(), 2.0, 1e-6);

  // A 2-D pose (1, 0.5, yaw 0.2) in root.
  auto pose2d = tree.transform_pose("room", "root", pose_xyz_euler({1.0, 0.5, 0.0}, {0., 0., 0.2}), 1000);
  ASSERT_TRUE(pose2d.ok()) << pose2d.error().to_string();
  EXPECT_NEAR(pose2d->translation().x(), -3.0, 1e-6);
  EXPECT_NEAR(pose2d->translation().y(), 0.5, 1e-6);
  EXPECT_NEAR(yaw_of(*pose2d), 0.2, 1e-6);

  // A 3-D pose (1, 0.5, 0, 0, 0, 0.2) in root.
  auto pose3d = tree.transform_pose("room", "root", pose_xyz_euler({1.0, 0.5, 0.0}, {0., 0., 0.2}), 1000);
  ASSERT_TRUE(pose3d.ok()) << pose3d.error().to_string();
  EXPECT_NEAR(pose3d->translation().x(), -3.0, 1e-6);
  EXPECT_NEAR(pose3d->translation().y(), 0.5, 1e-6);
  const Eigen::Vector3d rxyz = pose3d->linear().eulerAngles(0, 1, 2);
  EXPECT_NEAR(rxyz.z(), 0.2, 1e-6);
  EXPECT_NEAR(rxyz.x(), 0.0, 1e-6);
  EXPECT_NEAR(rxyz.y(), 0.0, 1e-6);
}

}  // namespace
}  // namespace quiver::cortex_tests
