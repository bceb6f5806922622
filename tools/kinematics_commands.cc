// quiver lookup / import-urdf: the kinematics module from the command line; and the options of
// quiver bench transforms / bench scene, whose runs are tools/bench's (quiver_bench).

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "commands.h"
#include "quiver/agents/runtime/process/logging.h"
#include "quiver/base/hash.h"
#include "quiver/graph/graph.h"
#include "quiver/graph/world_file.h"
#include "quiver/kinematics/frames.h"
#include "quiver/kinematics/urdf_import.h"
#include "quiver/tools/bench/scene_bench.h"
#include "quiver/tools/bench/transform_bench.h"

namespace quiver::tools {
namespace {

using graph::Graph;
using graph::ReplicaId;

// ---------------------------------------------------------------------------- quiver lookup

struct LookupArgs {
  std::string world;
  std::string a, b;
  std::optional<std::int64_t> at;
  bool json = false;
};

void run_lookup(const LookupArgs& args) {
  Graph g(ReplicaId{fnv1a64("quiver-lookup"), 1});
  auto loaded = graph::load_world_file(g, args.world);
  if (!loaded.ok()) {
    agents::named_logger("quiver lookup")->error("{}", loaded.error().message);
    set_exit_code(2);
    return;
  }
  kinematics::FrameTree tree(g);
  auto X = args.at ? tree.lookup_at(args.a, args.b, *args.at) : tree.lookup(args.a, args.b);
  if (!X.ok()) {
    agents::named_logger("quiver lookup")
        ->error("{}: {}", to_string(X.error().code), X.error().message);
    set_exit_code(1);
    return;
  }
  const Eigen::Vector3d p = X->translation();
  const Eigen::Quaterniond q(X->linear());
  // URDF convention: R = Rz(yaw)·Ry(pitch)·Rx(roll).
  const Eigen::Matrix3d R = X->linear();
  const double pitch = std::asin(std::clamp(-R(2, 0), -1.0, 1.0));
  double roll, yaw;
  if (std::abs(R(2, 0)) < 1.0 - 1e-12) {
    roll = std::atan2(R(2, 1), R(2, 2));
    yaw = std::atan2(R(1, 0), R(0, 0));
  } else {  // gimbal lock: put everything in yaw
    roll = 0.0;
    yaw = std::atan2(-R(0, 1), R(1, 1));
  }
  if (args.json) {
    nlohmann::json j;
    j["parent"] = args.a;
    j["child"] = args.b;
    if (args.at) j["at"] = *args.at;
    j["translation"] = {p.x(), p.y(), p.z()};
    j["rotation"] = {q.w(), q.x(), q.y(), q.z()};
    j["rpy"] = {roll, pitch, yaw};
    std::vector<double> m;
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) m.push_back(X->matrix()(r, c));
    j["matrix"] = m;
    std::cout << j.dump() << std::endl;
    return;
  }
  std::printf("X_%s_%s%s\n", args.a.c_str(), args.b.c_str(),
              args.at ? (" at " + std::to_string(*args.at)).c_str() : " (latest)");
  std::printf("  translation [m]       %.9g %.9g %.9g\n", p.x(), p.y(), p.z());
  std::printf("  rotation (w x y z)    %.9g %.9g %.9g %.9g\n", q.w(), q.x(), q.y(), q.z());
  std::printf("  rpy [rad]             %.9g %.9g %.9g\n", roll, pitch, yaw);
  std::printf("  rpy [deg]             %.6g %.6g %.6g\n", roll * 180 / M_PI, pitch * 180 / M_PI,
              yaw * 180 / M_PI);
}

// ---------------------------------------------------------------------------- import-urdf

struct UrdfImportArgs {
  std::string urdf;
  std::string out;
  std::string parent;
  std::string prefix;
};

void run_import(const UrdfImportArgs& args) {
  Graph g(ReplicaId{fnv1a64("quiver-import-urdf"), 1});
  kinematics::UrdfImportOptions opt;
  opt.parent = args.parent;
  opt.prefix = args.prefix;
  auto info = kinematics::import_urdf_file(g, args.urdf, opt);
  if (!info.ok()) {
    agents::named_logger("quiver import-urdf")->error("{}", info.error().message);
    set_exit_code(1);
    return;
  }
  Status s = graph::save_world_file(g, args.out);
  if (!s.ok()) {
    agents::named_logger("quiver import-urdf")->error("{}", s.error().message);
    set_exit_code(2);
    return;
  }
  nlohmann::json j;
  j["robot"] = info->robot;
  j["links"] = info->links;
  j["joints"] = info->joints;
  j["shapes"] = info->shapes;
  j["output"] = args.out;
  std::cout << j.dump() << std::endl;
}

}  // namespace

void add_kinematics_commands(CLI::App& app) {
  // quiver lookup
  auto la = std::make_shared<LookupArgs>();
  auto* lookup =
      app.add_subcommand("lookup", "Print X_AB, the pose of frame B in frame A, from a world file");
  lookup->add_option("world", la->world, "world file (JSON)")->required()->check(CLI::ExistingFile);
  lookup->add_option("A", la->a, "frame A (the frame the result is expressed in)")->required();
  lookup->add_option("B", la->b, "frame B")->required();
  lookup->add_option("--at", la->at,
                     "replicated time (the RT stamps' unit) instead of the latest poses");
  lookup->add_flag("--json", la->json, "print one JSON object");
  lookup->callback([la] { run_lookup(*la); });

  // quiver import-urdf
  auto ia = std::make_shared<UrdfImportArgs>();
  auto* imp =
      app.add_subcommand("import-urdf", "Convert a URDF robot description into a world file");
  imp->add_option("urdf", ia->urdf, "URDF file")->required()->check(CLI::ExistingFile);
  imp->add_option("-o,--output", ia->out, "world file to write")->required();
  imp->add_option("--parent", ia->parent,
                  "attach the robot's root link under this frame (created as type 'world')");
  imp->add_option("--prefix", ia->prefix, "prefix for every node name (e.g. 'robot1/')");
  imp->callback([ia] { run_import(*ia); });

  // quiver bench transforms / scene
  CLI::App* bench = app.get_subcommand("bench");
  auto tb = std::make_shared<bench::TransformBench>();
  auto* tr = bench->add_subcommand(
      "transforms", "Transform lookups on the two-branch tree we also run against tf2");
  tr->add_option("--depth", tb->depth, "frames per branch")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  tr->add_option("--lookups", tb->lookups, "lookups per reader and mode")
      ->check(CLI::Range(1L, 10'000'000'000L))
      ->capture_default_str();
  tr->add_option("--threads", tb->threads, "reader threads")
      ->check(CLI::Range(1, 64))
      ->capture_default_str();
  tr->add_option("--writer-hz", tb->writer_hz,
                 "a writer commits a new sample on every edge at this rate")
      ->check(CLI::Range(0.0, 100000.0))
      ->capture_default_str();
  tr->add_flag("--handles", tb->handles, "look up by pre-resolved frame handles instead of names");
  tr->callback([tb] { set_exit_code(bench::run_transform_bench(*tb)); });

  auto sb = std::make_shared<bench::SceneBench>();
  auto* sc = bench->add_subcommand(
      "scene", "Cost of one moved object's update in the FCL scene, for growing scenes");
  sc->add_option("--objects", sb->objects, "scene sizes")
      ->check(CLI::Range(1, 10'000'000))
      ->capture_default_str();
  sc->add_option("--moves", sb->moves, "moves per size")
      ->check(CLI::Range(1, 100'000'000))
      ->capture_default_str();
  sc->callback([sb] { set_exit_code(bench::run_scene_bench(*sb)); });
}

}  // namespace quiver::tools
