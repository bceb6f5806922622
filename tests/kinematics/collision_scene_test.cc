// The FCL scene against analytic sphere/box answers, following the graph incrementally.

#include "quiver/kinematics/collision_scene.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "kin_test_util.h"
#include "test_seed.h"

namespace quiver::kinematics {
namespace {

using graph::Graph;
using graph::NodeId;
using graph::Pose;
using graph::ReplicaId;
using graph::Symbol;
using graph::Value;
using testing::iso;
using testing::random_pose;
using testing::ref_root_pose;

std::vector<std::pair<Symbol, Value>> sphere(double r) {
  ShapeSpec s;
  s.kind = ShapeSpec::Kind::kSphere;
  s.radius = r;
  return shape_attributes(s);
}
std::vector<std::pair<Symbol, Value>> box(float x, float y, float z) {
  ShapeSpec s;
  s.kind = ShapeSpec::Kind::kBox;
  s.size = Eigen::Vector3d(x, y, z);
  return shape_attributes(s);
}

Eigen::Vector3d center(const Graph& g, NodeId n) {
  return ref_root_pose(g, n).second.translation();
}

/// A world with two intermediate frames (so objects sit under rotated parents).
struct World {
  Graph g{ReplicaId{1, 1}};
  NodeId w, p1, p2;
  explicit World(Rng& rng) {
    auto tx = g.begin();
    w = *tx.create_node("world", "world");
    p1 = *tx.create_node("f", "p1");
    p2 = *tx.create_node("f", "p2");
    (void)tx.set_rt(w, p1, random_pose(rng, 0.5));
    (void)tx.set_rt(w, p2, random_pose(rng, 0.5));
    (void)tx.commit();
  }
  NodeId add(const std::string& name, NodeId parent, const Pose& X,
             std::vector<std::pair<Symbol, Value>> attrs) {
    auto tx = g.begin();
    NodeId id = *tx.create_node("object", name, std::move(attrs));
    if (!parent.is_null()) {
      EXPECT_TRUE(tx.set_rt(parent, id, X).ok());
    }
    EXPECT_TRUE(tx.commit().ok());
    return id;
  }
  void move(NodeId child, const Pose& X, std::int64_t stamp = 0) {
    auto tx = g.begin();
    EXPECT_TRUE(tx.set_rt(*g.rt_parent(child), child, X, stamp).ok());
    EXPECT_TRUE(tx.commit().ok());
  }
};

TEST(CollisionSceneTest, SphereSphereMatchesAnalyticDistances) {
  const std::uint64_t base = quiver::testing::base_seed("CollisionSceneTest.SphereSphere", 404);
  Rng rng(base);
  World world(rng);
  const double ra = 0.3, rb = 0.5;
  NodeId a = world.add("a", world.p1, random_pose(rng), sphere(ra));
  NodeId b = world.add("b", world.p2, random_pose(rng), sphere(rb));
  FrameTree tree(world.g);
  CollisionScene scene(tree);
  ASSERT_EQ(scene.object_count(), 2u);
  int separated = 0, touching = 0;
  for (int i = 0; i < 300; ++i) {
    world.move(a, random_pose(rng, 0.6), i);
    world.move(b, random_pose(rng, 0.6), i);
    const Eigen::Vector3d ca = center(world.g, a), cb = center(world.g, b);
    const double gap = (cb - ca).norm() - ra - rb;
    if (std::abs(gap) < 1e-3) continue;  // too close to call
    auto d = scene.distance("a", "b");
    ASSERT_TRUE(d.ok()) << d.error().to_string();
    auto c = scene.collide("a", "b");
    ASSERT_TRUE(c.ok());
    EXPECT_EQ(c->in_collision, gap < 0) << "gap " << gap;
    EXPECT_EQ(d->in_collision, gap < 0);
    if (gap > 0) {
      ++separated;
      EXPECT_NEAR(d->distance, gap, 1e-6);
      // Nearest points, in frame a: on each surface along the line between the centres.
      const Eigen::Isometry3d X_aW = ref_root_pose(world.g, a).second.inverse();
      const Eigen::Vector3d u = (cb - ca).normalized();
      EXPECT_NEAR((d->p_AoPa_A - X_aW * (ca + ra * u)).norm(), 0.0, 1e-5);
      EXPECT_NEAR((d->p_AoPb_A - X_aW * (cb - rb * u)).norm(), 0.0, 1e-5);
    } else {
      ++touching;
      EXPECT_EQ(d->distance, 0.0);
      EXPECT_GT(c->penetration_depth, 0.0);
      EXPECT_NEAR(c->penetration_depth, -gap, 1e-5);
    }
  }
  EXPECT_GT(separated, 20);
  EXPECT_GT(touching, 20);
  // Only moved objects were updated; the scene was built once.
  EXPECT_EQ(scene.stats().full_rebuilds, 1u);
  EXPECT_EQ(scene.stats().objects_updated, 600u);
}

TEST(CollisionSceneTest, SphereBoxMatchesAnalyticDistance) {
  const std::uint64_t base = quiver::testing::base_seed("CollisionSceneTest.SphereBox", 405);
  Rng rng(base);
  World world(rng);
  const Eigen::Vector3d half(0.4, 0.25, 0.1);
  const double r = 0.2;
  NodeId bx = world.add("box", world.p1, random_pose(rng), box(0.8f, 0.5f, 0.2f));
  NodeId s = world.add("ball", world.p2, random_pose(rng), sphere(r));
  FrameTree tree(world.g);
  CollisionScene scene(tree);
  int checked = 0;
  for (int i = 0; i < 300; ++i) {
    world.move(s, random_pose(rng, 1.2), i);
    // The sphere's centre in the box frame; the closest box point is the clamped centre.
    const Eigen::Isometry3d X_BW = ref_root_pose(world.g, bx).second.inverse();
    const Eigen::Vector3d c_B = X_BW * center(world.g, s);
    const Eigen::Vector3d n_B = c_B.cwiseMax(-half).cwiseMin(half);
    const double outside = (c_B - n_B).norm();
    if (outside == 0.0) continue;  // centre inside the box
    const double gap = outside - r;
    if (std::abs(gap) < 1e-3) continue;
    auto d = scene.distance("box", "ball");
    ASSERT_TRUE(d.ok()) << d.error().to_string();
    auto c = scene.collide("ball", "box");
    ASSERT_TRUE(c.ok());
    EXPECT_EQ(c->in_collision, gap < 0) << "gap " << gap;
    if (gap > 0) {
      EXPECT_NEAR(d->distance, gap, 1e-6);
      EXPECT_NEAR((d->p_AoPa_A - n_B).norm(), 0.0, 1e-5);  // frame A is the box frame
      ++checked;
    }
  }
  EXPECT_GT(checked, 50);
}

TEST(CollisionSceneTest, AllPairsInContactAndIncrementalUpdates) {
  const std::uint64_t base = quiver::testing::base_seed("CollisionSceneTest.AllPairs", 406);
  const int seeds = quiver::testing::seed_count(3);
  for (int k = 0; k < seeds; ++k) {
    Rng rng(base + k);
    World world(rng);
    std::vector<NodeId> balls;
    std::vector<double> radius;
    for (int i = 0; i < 30; ++i) {
      radius.push_back(0.05 + 0.2 * rng.uniform());
      balls.push_back(world.add("ball" + std::to_string(i), rng.chance(0.5) ? world.p1 : world.p2,
                                random_pose(rng, 1.5), sphere(radius.back())));
    }
    // A second tree: never in contact with the first, whatever the coordinates say.
    NodeId island =
        world.add("island", world.add("island_root", NodeId{}, Pose{}, {}), Pose{}, sphere(5.0));
    (void)island;
    FrameTree tree(world.g);
    CollisionScene scene(tree);
    for (int round = 0; round < 20; ++round) {
      // Move a few balls, and sometimes a whole parent frame (its subtree moves with it).
      auto before = scene.stats();
      std::size_t moved = 0;
      for (int m = 0; m < 3; ++m) {
        world.move(balls[rng.below(balls.size())], random_pose(rng, 1.5), round);
        ++moved;
      }
      if (round % 5 == 4) {
        auto tx = world.g.begin();
        (void)tx.set_rt(world.w, world.p1, random_pose(rng, 1.0), round);
        (void)tx.commit();
        for (const NodeId& b : balls)
          if (*world.g.rt_parent(b) == world.p1) ++moved;
      }
      EXPECT_EQ(scene.stats().objects_updated - before.objects_updated, moved);
      EXPECT_EQ(scene.stats().full_rebuilds, 1u);
      // Brute force: every pair of spheres whose centres are closer than the radii sum.
      std::vector<std::pair<NodeId, NodeId>> want;
      for (std::size_t i = 0; i < balls.size(); ++i)
        for (std::size_t j = i + 1; j < balls.size(); ++j) {
          const double gap = (center(world.g, balls[i]) - center(world.g, balls[j])).norm() -
                             radius[i] - radius[j];
          if (std::abs(gap) < 1e-6) continue;
          if (gap < 0)
            want.emplace_back(std::min(balls[i], balls[j]), std::max(balls[i], balls[j]));
        }
      std::sort(want.begin(), want.end());
      EXPECT_EQ(scene.colliding_pairs(), want) << "round " << round;
    }
  }
}

TEST(CollisionSceneTest, ShapesFollowAttributesAndErrorsAreClear) {
  Rng rng(1);
  World world(rng);
  NodeId a = world.add("a", world.w, Pose{{0, 0, 0}, {1, 0, 0, 0}}, sphere(0.5));
  NodeId b = world.add("b", world.w, Pose{{2, 0, 0}, {1, 0, 0, 0}}, sphere(0.5));
  NodeId plain = world.add("plain", world.w, Pose{{0, 3, 0}, {1, 0, 0, 0}}, {});
  FrameTree tree(world.g);
  CollisionScene scene(tree);
  EXPECT_NEAR(scene.distance("a", "b")->distance, 1.0, 1e-9);
  // Growing a's radius rebuilds its shape alone.
  {
    auto tx = world.g.begin();
    ASSERT_TRUE(tx.set(a, "shape_radius", Value(0.75)).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  EXPECT_NEAR(scene.distance("a", "b")->distance, 0.75, 1e-9);
  // A capsule and a cylinder along z, seen from the side.
  {
    auto tx = world.g.begin();
    ASSERT_TRUE(tx.set(b, "shape", Value("capsule")).ok());
    ASSERT_TRUE(tx.set(b, "shape_length", Value(1.0)).ok());
    ASSERT_TRUE(tx.set(b, "shape_radius", Value(0.25)).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  EXPECT_NEAR(scene.distance("a", "b")->distance, 2.0 - 0.75 - 0.25, 1e-6);
  // Invalid shapes are reported by name and kept out of the scene.
  {
    auto tx = world.g.begin();
    ASSERT_TRUE(tx.set(b, "shape", Value("blob")).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  auto bad = scene.distance("a", "b");
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().code, ErrorCode::kInvalidArgument);
  EXPECT_NE(bad.error().message.find("unknown shape 'blob'"), std::string::npos)
      << bad.error().message;
  ASSERT_EQ(scene.problems().size(), 1u);
  auto none = scene.collide("a", "plain");
  ASSERT_FALSE(none.ok());
  EXPECT_NE(none.error().message.find("has no collision shape"), std::string::npos)
      << none.error().message;
  auto unknown = scene.collide("a", "ghost");
  ASSERT_FALSE(unknown.ok());
  EXPECT_EQ(unknown.error().code, ErrorCode::kNotFound);
  // A box missing its size.
  {
    auto tx = world.g.begin();
    ASSERT_TRUE(tx.set(b, "shape", Value("box")).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  auto bad_box = scene.collide("a", "b");
  ASSERT_FALSE(bad_box.ok());
  EXPECT_NE(bad_box.error().message.find("needs the attribute 'shape_size'"), std::string::npos)
      << bad_box.error().message;
  // Deleting a node removes its object.
  {
    auto tx = world.g.begin();
    ASSERT_TRUE(tx.delete_node(a).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  EXPECT_EQ(scene.object_count(), 0u);
  (void)plain;
}

TEST(CollisionSceneTest, SeparateTreesAreNotConnected) {
  Rng rng(2);
  World world(rng);
  world.add("a", world.w, Pose{}, sphere(0.5));
  NodeId root2 = world.add("table", NodeId{}, Pose{}, {});
  world.add("b", root2, Pose{}, sphere(0.5));  // same coordinates, another tree
  FrameTree tree(world.g);
  CollisionScene scene(tree);
  auto c = scene.collide("a", "b");
  ASSERT_FALSE(c.ok());
  EXPECT_EQ(c.error().code, ErrorCode::kNotConnected);
  EXPECT_TRUE(scene.colliding_pairs().empty());
}

TEST(CollisionSceneTest, WithinReach) {
  Rng rng(3);
  World world(rng);
  NodeId shoulder = world.add("shoulder", world.w, Pose{{0, 0, 1}, {1, 0, 0, 0}}, {});
  // A mug (r = 0.05) whose centre is 0.8 m from the shoulder along x of the shoulder frame.
  world.add("mug", world.w, Pose{{0.8, 0, 1}, {1, 0, 0, 0}}, sphere(0.05));
  world.add("mark", world.w, Pose{{0, 0.6, 1}, {1, 0, 0, 0}}, {});
  world.add("shelf", world.w, Pose{{0, 0, 2}, {1, 0, 0, 0}}, box(2.0f, 2.0f, 0.2f));
  (void)shoulder;
  FrameTree tree(world.g);
  CollisionScene scene(tree);
  auto r = scene.within_reach("mug", "shoulder", 0.76);
  ASSERT_TRUE(r.ok()) << r.error().to_string();
  EXPECT_TRUE(r->reachable);
  EXPECT_NEAR(r->distance, 0.75, 1e-6);
  EXPECT_NEAR((r->p_BoN_B - Eigen::Vector3d(0.75, 0, 0)).norm(), 0.0, 1e-5);
  EXPECT_FALSE(scene.within_reach("mug", "shoulder", 0.74)->reachable);
  // Without a shape, the target is its origin.
  EXPECT_NEAR(scene.within_reach("mark", "shoulder", 1.0)->distance, 0.6, 1e-12);
  // The shelf's underside is 0.9 m above the shoulder.
  EXPECT_NEAR(scene.within_reach("shelf", "shoulder", 1.0)->distance, 0.9, 1e-6);
  EXPECT_FALSE(scene.within_reach("mug", "shoulder", -1.0).ok());
}

TEST(CollisionSceneTest, MeshFilesAsShapes) {
  const auto dir =
      std::filesystem::temp_directory_path() / ("quiver_mesh_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  // A 1 m cube centred on the origin, as OBJ (quads) and as binary STL (triangles).
  const std::string obj = (dir / "cube.obj").string();
  {
    std::ofstream f(obj);
    f << "# cube\n";
    for (int i = 0; i < 8; ++i)
      f << "v " << ((i & 1) ? 0.5 : -0.5) << " " << ((i & 2) ? 0.5 : -0.5) << " "
        << ((i & 4) ? 0.5 : -0.5) << "\n";
    f << "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
  }
  auto mesh = load_mesh(obj);
  ASSERT_TRUE(mesh.ok()) << mesh.error().to_string();
  EXPECT_EQ(mesh->vertices.size(), 8u);
  EXPECT_EQ(mesh->triangles.size(), 12u);
  const std::string stl = (dir / "cube.stl").string();
  {
    std::ofstream f(stl, std::ios::binary);
    std::string header(80, ' ');
    f.write(header.data(), 80);
    const std::uint32_t n = static_cast<std::uint32_t>(mesh->triangles.size());
    f.write(reinterpret_cast<const char*>(&n), 4);
    for (const auto& t : mesh->triangles) {
      float normal[3] = {0, 0, 0};
      f.write(reinterpret_cast<const char*>(normal), 12);
      for (int v : t) {
        float p[3] = {float(mesh->vertices[v].x()), float(mesh->vertices[v].y()),
                      float(mesh->vertices[v].z())};
        f.write(reinterpret_cast<const char*>(p), 12);
      }
      std::uint16_t attr = 0;
      f.write(reinterpret_cast<const char*>(&attr), 2);
    }
  }
  ASSERT_TRUE(load_mesh(stl).ok());
  const std::string broken = (dir / "broken.obj").string();
  std::ofstream(broken) << "v 0 0 0\nf 1 2 3\n";
  auto err = load_mesh(broken);
  ASSERT_FALSE(err.ok());
  EXPECT_EQ(err.error().code, ErrorCode::kMalformed);
  EXPECT_NE(err.error().message.find("broken.obj:2"), std::string::npos) << err.error().message;

  Rng rng(4);
  World world(rng);
  world.add("cube_obj", world.w, Pose{{0, 0, 0}, {1, 0, 0, 0}},
            {{Symbol("shape"), Value("mesh")}, {Symbol("shape_mesh"), Value(obj)}});
  world.add("cube_stl", world.w, Pose{{0, 0, 3}, {1, 0, 0, 0}},
            {{Symbol("shape"), Value("mesh")},
             {Symbol("shape_mesh"), Value(stl)},
             {Symbol("shape_scale"), Value(graph::Vec3f{2, 2, 2})}});
  world.add("ball", world.w, Pose{{2, 0, 0}, {1, 0, 0, 0}}, sphere(0.25));
  world.add("broken", world.w, Pose{},
            {{Symbol("shape"), Value("mesh")}, {Symbol("shape_mesh"), Value(broken)}});
  FrameTree tree(world.g);
  CollisionScene scene(tree);
  auto d = scene.distance("cube_obj", "ball");
  ASSERT_TRUE(d.ok()) << d.error().to_string();
  EXPECT_NEAR(d->distance, 2.0 - 0.5 - 0.25, 1e-4);
  // The STL cube is scaled to 2 m: its bottom face is at z = 3 − 1 = 2, the OBJ cube's top at 0.5.
  auto d2 = scene.distance("cube_obj", "cube_stl");
  ASSERT_TRUE(d2.ok());
  EXPECT_NEAR(d2->distance, 1.5, 1e-4);
  ASSERT_EQ(scene.problems().size(), 1u);
  EXPECT_NE(scene.problems()[0].second.find("broken.obj"), std::string::npos);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace quiver::kinematics
