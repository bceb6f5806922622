// Kinematics: a world file, a robot arm from its URDF, and transforms between any two frames,
// now and in the past. Run from the repository root:
//   kinematics_lookup examples/worlds/kitchen.json examples/urdf/arm.urdf
#include <cstdio>
#include <string>

#include "quiver/graph/world_file.h"
#include "quiver/kinematics/frames.h"
#include "quiver/kinematics/urdf_import.h"
using namespace quiver;

int main(int argc, char** argv) {
  graph::Graph graph(graph::ReplicaId{fnv1a64("kinematics_lookup"), /*incarnation=*/1});
  auto world = graph::load_world_file(graph, argc > 1 ? argv[1] : "examples/worlds/kitchen.json");
  kinematics::UrdfImportOptions mount;
  mount.parent = "robot";  // the arm's root link hangs under the robot node
  auto arm = kinematics::import_urdf_file(graph, argc > 2 ? argv[2] : "examples/urdf/arm.urdf", mount);
  if (!world.ok() || !arm.ok()) {
    std::fprintf(stderr, "%s\n", (world.ok() ? arm.error() : world.error()).to_string().c_str());
    return 1;
  }

  // The person walks 1 m along x in one second: two timed samples of world -> person.
  const graph::NodeId world_frame = *graph.find_node("world");
  const graph::NodeId person = *graph.find_node("person");
  const kinematics::Time t = 2'000'000'000;  // replicated time, nanoseconds
  for (int i = 0; i < 2; ++i) {
    auto tx = graph.begin();
    graph::Pose X_WP{{3.0 + i, 1.0, 0.0}, {1.0, 0.0, 0.0, 0.0}};
    auto moved = tx.set_rt(world_frame, person, X_WP, t - 1'000'000'000 + i * 1'000'000'000);
    if (!moved.ok() || !tx.commit().ok()) return 1;
  }

  kinematics::FrameTree tree(graph);             // follows local commits and merges
  auto X_GM = tree.lookup("gripper", "mug");      // X_AB: the mug in the gripper's frame
  auto reader = tree.reader();                    // for another thread
  auto X_WP = reader.lookup_at("world", "person", t - 500'000'000);  // 500 ms ago
  if (!X_GM.ok() || !X_WP.ok()) {
    std::fprintf(stderr, "%s\n", (X_GM.ok() ? X_WP.error() : X_GM.error()).to_string().c_str());
    return 1;
  }
  const auto p_GM = X_GM->translation();
  const auto p_WP = X_WP->translation();
  std::printf("%s: %zu links, %zu joints\n", arm->robot.c_str(), arm->links, arm->joints);
  std::printf("mug in the gripper's frame: [%.3f, %.3f, %.3f]\n", p_GM.x(), p_GM.y(), p_GM.z());
  std::printf("person 500 ms ago, in the world: [%.3f, %.3f, %.3f]\n", p_WP.x(), p_WP.y(), p_WP.z());
  return 0;
}
