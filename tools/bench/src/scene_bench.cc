// The collision scene benchmark (`quiver bench scene`): one object moved per transaction in
// scenes of growing size, the scene's own update timed.
#include "quiver/tools/bench/scene_bench.h"

#include <chrono>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "quiver/base/hash.h"
#include "quiver/base/rng.h"
#include "quiver/graph/graph.h"
#include "quiver/kinematics/collision_scene.h"
#include "quiver/kinematics/frames.h"
#include "quiver/kinematics/shape.h"
#include "quiver/base/percentiles.h"
#include "quiver/tools/bench/bench_util.h"

namespace quiver::tools::bench {

using Clock = std::chrono::steady_clock;
using graph::Graph;
using graph::NodeId;
using graph::Pose;
using graph::ReplicaId;

int run_scene_bench(const SceneBench& b) {
  kinematics::ShapeSpec ball;
  ball.kind = kinematics::ShapeSpec::Kind::kSphere;
  ball.radius = 0.05;
  for (int n : b.objects) {
    Graph g(ReplicaId{fnv1a64("bench-scene"), 1});
    Rng rng(11);
    std::vector<NodeId> ids;
    NodeId world;
    {
      auto tx = g.begin();
      world = *tx.create_node("world", "world");
      (void)tx.commit();
    }
    for (int i = 0; i < n;) {  // transactions of 1000 (validation cost grows with their size)
      auto tx = g.begin();
      for (int k = 0; k < 1000 && i < n; ++k, ++i) {
        NodeId id =
            *tx.create_node("object", "o" + std::to_string(i), kinematics::shape_attributes(ball));
        Pose p;
        p.translation = {rng.uniform() * 100, rng.uniform() * 100, rng.uniform() * 2};
        (void)tx.set_rt(world, id, p, 0);
        ids.push_back(id);
      }
      (void)tx.commit();
    }
    kinematics::FrameTree tree(g);
    // Time the scene's own work: listeners run in registration order, so one registered before
    // the scene and one after bracket its update.
    Clock::time_point scene_t0;
    double scene_s = 0;
    tree.add_listener([&](const kinematics::FrameUpdate&) { scene_t0 = Clock::now(); });
    auto t_build = Clock::now();
    kinematics::CollisionScene scene(tree);
    const double build_s = seconds_since(t_build);
    tree.add_listener([&](const kinematics::FrameUpdate&) { scene_s += seconds_since(scene_t0); });
    const auto before = scene.stats();
    // The moves: a small random walk of one object per transaction.
    std::vector<Pose> poses(n);
    for (int i = 0; i < n; ++i) poses[i] = g.rt_edge(ids[i])->pose;
    auto t0 = Clock::now();
    for (int m = 0; m < b.moves; ++m) {
      const std::size_t k = rng.below(ids.size());
      Pose& p = poses[k];
      for (auto& x : p.translation) x += (rng.uniform() - 0.5) * 0.2;
      auto tx = g.begin();
      (void)tx.set_rt(world, ids[k], p, m + 1);
      (void)tx.commit();
    }
    const double total_s = seconds_since(t0);
    const auto after = scene.stats();
    nlohmann::json j;
    j["bench"] = "scene";
    j["objects"] = n;
    j["moves"] = b.moves;
    j["build_ms"] = round_to(build_s * 1e3, 2);
    j["scene_update_us"] = round_to(scene_s / b.moves * 1e6, 3);
    j["move_total_us"] = round_to(total_s / b.moves * 1e6, 3);
    j["objects_updated"] = after.objects_updated - before.objects_updated;
    j["full_rebuilds"] = after.full_rebuilds - before.full_rebuilds;
    std::cout << j.dump() << std::endl;
  }
  return 0;
}

}  // namespace quiver::tools::bench
