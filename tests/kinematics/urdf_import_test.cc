// URDF import: links, joints with their origins, collision shapes, options, malformed input.

#include "quiver/kinematics/urdf_import.h"

#include <gtest/gtest.h>

#include "kin_test_util.h"
#include "quiver/graph/world_file.h"
#include "quiver/kinematics/frames.h"
#include "quiver/kinematics/shape.h"

namespace quiver::kinematics {
namespace {

using graph::Graph;
using graph::ReplicaId;
using testing::max_abs_diff;

constexpr const char* kArm = R"(<?xml version="1.0"?>
<robot name="arm">
  <link name="base_link">
    <collision><geometry><box size="0.4 0.3 0.1"/></geometry></collision>
  </link>
  <link name="link1">
    <collision>
      <origin xyz="0 0 0.25" rpy="0 0 0"/>
      <geometry><cylinder radius="0.05" length="0.5"/></geometry>
    </collision>
  </link>
  <link name="link2">
    <collision><geometry><sphere radius="0.04"/></geometry><origin xyz="0.1 0 0"/></collision>
    <collision><geometry><mesh filename="meshes/gripper.stl" scale="0.001 0.001 0.001"/></geometry></collision>
  </link>
  <link name="tool"/>
  <joint name="shoulder" type="revolute">
    <parent link="base_link"/><child link="link1"/>
    <origin xyz="0 0 0.1" rpy="0.1 0.2 0.3"/>
    <axis xyz="0 0 1"/>
    <limit lower="-1.5" upper="1.5" effort="10" velocity="2"/>
  </joint>
  <joint name="slide" type="prismatic">
    <parent link="link1"/><child link="link2"/>
    <origin xyz="0 0.05 0.5" rpy="0 1.5707963267948966 0"/>
    <axis xyz="1 0 0"/>
    <limit lower="0" upper="0.2" effort="5" velocity="0.1"/>
  </joint>
  <joint name="flange" type="fixed">
    <parent link="link2"/><child link="tool"/>
    <origin xyz="0.2 0 0"/>
  </joint>
</robot>)";

Eigen::Isometry3d xyz_rpy(double x, double y, double z, double r, double p, double yaw) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(p, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(r, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  X.translation() = Eigen::Vector3d(x, y, z);
  return X;
}

TEST(UrdfImportTest, LinksJointsAndShapes) {
  Graph g(ReplicaId{1, 1});
  UrdfImportOptions opt;
  opt.base_dir = "/robots/arm";
  auto info = import_urdf(g, kArm, opt, "arm.urdf");
  ASSERT_TRUE(info.ok()) << info.error().to_string();
  EXPECT_EQ(info->robot, "arm");
  EXPECT_EQ(info->links, 4u);
  EXPECT_EQ(info->joints, 3u);
  EXPECT_EQ(info->shapes, 4u);
  // 4 links + 3 collision nodes (link1 has an offset collision, link2 has two).
  EXPECT_EQ(g.node_count(), 7u);
  EXPECT_EQ(g.type_of(*g.find_node("link1")).str(), "link");

  FrameTree tree(g);
  const Eigen::Isometry3d X_BL1 = xyz_rpy(0, 0, 0.1, 0.1, 0.2, 0.3);
  const Eigen::Isometry3d X_L1L2 = xyz_rpy(0, 0.05, 0.5, 0, M_PI / 2, 0);
  const Eigen::Isometry3d X_L2T = xyz_rpy(0.2, 0, 0, 0, 0, 0);
  auto X = tree.lookup("base_link", "tool");
  ASSERT_TRUE(X.ok()) << X.error().to_string();
  EXPECT_LT(max_abs_diff(*X, X_BL1 * X_L1L2 * X_L2T), 1e-12);
  auto root = tree.root_pose("tool");
  ASSERT_TRUE(root.ok());
  EXPECT_EQ(root->first, *tree.frame("base_link"));

  // Joints as attributes of their child link.
  const auto link1 = *g.find_node("link1");
  EXPECT_EQ(*g.get<std::string>(link1, "joint"), "shoulder");
  EXPECT_EQ(*g.get<std::string>(link1, "joint_type"), "revolute");
  EXPECT_EQ(*g.get<graph::Vec3f>(link1, "joint_axis"), (graph::Vec3f{0, 0, 1}));
  EXPECT_EQ(*g.get<double>(link1, "joint_lower"), -1.5);
  EXPECT_EQ(*g.get<double>(link1, "joint_upper"), 1.5);
  EXPECT_EQ(*g.get<std::string>(*g.find_node("tool"), "joint_type"), "fixed");

  // Shapes: inline on base_link; on child nodes where the collision has an offset or there are
  // several.
  auto base_shape = read_shape(g, *g.find_node("base_link"));
  ASSERT_TRUE(base_shape.ok() && base_shape->has_value());
  EXPECT_EQ((*base_shape)->kind, ShapeSpec::Kind::kBox);
  EXPECT_NEAR(((*base_shape)->size - Eigen::Vector3d(0.4, 0.3, 0.1)).norm(), 0.0, 1e-6);
  EXPECT_FALSE(read_shape(g, link1)->has_value());
  auto c0 = g.find_node("link1/collision_0");
  ASSERT_TRUE(c0.has_value());
  auto cyl = read_shape(g, *c0);
  ASSERT_TRUE(cyl.ok() && cyl->has_value());
  EXPECT_EQ((*cyl)->kind, ShapeSpec::Kind::kCylinder);
  EXPECT_NEAR((*cyl)->length, 0.5, 1e-12);
  auto X_c0 = tree.lookup("link1", "link1/collision_0");
  ASSERT_TRUE(X_c0.ok());
  EXPECT_NEAR((X_c0->translation() - Eigen::Vector3d(0, 0, 0.25)).norm(), 0.0, 1e-12);
  auto mesh = read_shape(g, *g.find_node("link2/collision_1"));
  ASSERT_TRUE(mesh.ok() && mesh->has_value());
  EXPECT_EQ((*mesh)->mesh, "/robots/arm/meshes/gripper.stl");
  EXPECT_NEAR((*mesh)->scale.x(), 0.001, 1e-9);

  // The world file written from it loads back to the same transforms.
  Graph g2(ReplicaId{2, 1});
  auto loaded = graph::load_world(g2, graph::save_world(g));
  ASSERT_TRUE(loaded.ok()) << loaded.error().to_string();
  FrameTree tree2(g2);
  auto X2 = tree2.lookup("base_link", "tool");
  ASSERT_TRUE(X2.ok());
  EXPECT_LT(max_abs_diff(*X2, *X), 1e-12);
}

TEST(UrdfImportTest, ParentAndPrefixPlaceSeveralRobots) {
  Graph g(ReplicaId{1, 1});
  UrdfImportOptions a;
  a.parent = "world";
  a.prefix = "r1/";
  a.X_PR.translation = {1, 0, 0};
  ASSERT_TRUE(import_urdf(g, kArm, a).ok());
  UrdfImportOptions b = a;
  b.prefix = "r2/";
  b.X_PR.translation = {-1, 0, 0};
  ASSERT_TRUE(import_urdf(g, kArm, b).ok());
  FrameTree tree(g);
  auto X = tree.lookup("r1/base_link", "r2/base_link");
  ASSERT_TRUE(X.ok()) << X.error().to_string();
  EXPECT_NEAR((X->translation() - Eigen::Vector3d(-2, 0, 0)).norm(), 0.0, 1e-12);
  // The same prefix again: refused, and nothing is added.
  const auto before = g.node_count();
  auto again = import_urdf(g, kArm, a);
  ASSERT_FALSE(again.ok());
  EXPECT_EQ(again.error().code, ErrorCode::kAlreadyExists);
  EXPECT_NE(again.error().message.find("r1/"), std::string::npos) << again.error().message;
  EXPECT_EQ(g.node_count(), before);
}

TEST(UrdfImportTest, MalformedUrdfGetsAClearError) {
  struct Case {
    const char* what;
    std::string xml;
    const char* expect;  // a piece of the message
  };
  const std::vector<Case> cases = {
      {"not XML", "<robot name='x'><link name='a'>", "arm.urdf"},
      {"no robot element", "<?xml version='1.0'?><model name='x'/>", "robot"},
      {"joint to a missing link",
       "<robot name='x'><link name='a'/><joint name='j' type='fixed'><parent link='a'/><child "
       "link='ghost'/></joint></robot>",
       "ghost"},
      {"two roots", "<robot name='x'><link name='a'/><link name='b'/></robot>", "root"},
      {"bad number",
       "<robot name='x'><link name='a'><collision><geometry><sphere "
       "radius='abc'/></geometry></collision></link></robot>",
       "radius"},
      {"zero-size box",
       "<robot name='x'><link name='a'><collision><geometry><box size='0 1 "
       "1'/></geometry></collision></link></robot>",
       "zero or negative size"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    Graph g(ReplicaId{1, 1});
    auto r = import_urdf(g, c.xml, {}, "arm.urdf");
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().code, ErrorCode::kMalformed) << r.error().to_string();
    EXPECT_NE(r.error().message.find("import_urdf(): arm.urdf"), std::string::npos)
        << r.error().message;
    EXPECT_NE(r.error().message.find(c.expect), std::string::npos) << r.error().message;
    EXPECT_EQ(g.node_count(), 0u);
  }
  Graph g(ReplicaId{1, 1});
  auto missing = import_urdf_file(g, "/nonexistent/robot.urdf");
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error().code, ErrorCode::kIo);
}

}  // namespace
}  // namespace quiver::kinematics
