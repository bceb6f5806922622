// quiver lookup / import-urdf / bench transforms / bench scene: the kinematics module from the
// command line.

#include <time.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>
#include <vector>

#include "bench_stats.h"
#include "bench_util.h"
#include "commands.h"
#include "quiver/agents/runtime/process/logging.h"
#include "quiver/graph/graph.h"
#include "quiver/graph/world_file.h"
#include "quiver/kinematics/collision_scene.h"
#include "quiver/kinematics/frames.h"
#include "quiver/kinematics/shape.h"
#include "quiver/kinematics/urdf_import.h"
#include "quiver/base/rng.h"

namespace quiver::tools {
namespace {

using Clock = std::chrono::steady_clock;
using graph::Graph;
using graph::NodeId;
using graph::Pose;
using graph::ReplicaId;

/// CPU time of the calling thread (what a reader consumed, whatever else the machine ran).
double thread_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

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
    agents::named_logger("quiver lookup")->error("{}: {}", to_string(X.error().code), X.error().message);
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

struct ImportArgs {
  std::string urdf;
  std::string out;
  std::string parent;
  std::string prefix;
};

void run_import(const ImportArgs& args) {
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

// ---------------------------------------------------------------------------- bench transforms

// The benchmark tree, the same one tools/bench_tf2.cc builds: see bench_pose() in bench_util.h.
Pose edge_pose(int branch, int i, int sample) {
  const BenchPose b = bench_pose(branch, i, sample);
  return Pose{b.translation, b.rotation};
}
constexpr std::int64_t kSecond = 1'000'000'000;

struct BenchTree {
  std::vector<NodeId> parent_of;  // per edge
  std::vector<NodeId> child_of;
  std::vector<std::pair<int, int>> edge_index;  // (branch, i)
  std::string leaf0, leaf1;
};

BenchTree build_bench_tree(Graph& g, int depth) {
  BenchTree t;
  auto tx = g.begin();
  NodeId world = *tx.create_node("world", "world");
  for (int k = 0; k < 2; ++k) {
    NodeId parent = world;
    for (int i = 1; i <= depth; ++i) {
      NodeId c = *tx.create_node("frame", "b" + std::to_string(k) + "_" + std::to_string(i));
      (void)tx.set_rt(parent, c, edge_pose(k, i, 0), 0);
      t.parent_of.push_back(parent);
      t.child_of.push_back(c);
      t.edge_index.emplace_back(k, i);
      parent = c;
    }
  }
  (void)tx.commit();
  for (int sample = 0; sample < 2; ++sample) {
    auto s = g.begin();
    for (std::size_t e = 0; e < t.child_of.size(); ++e)
      (void)s.set_rt(t.parent_of[e], t.child_of[e],
                     edge_pose(t.edge_index[e].first, t.edge_index[e].second, sample),
                     (sample + 1) * kSecond);
    (void)s.commit();
  }
  t.leaf0 = "b0_" + std::to_string(depth);
  t.leaf1 = "b1_" + std::to_string(depth);
  return t;
}

struct TransformBench {
  int depth = 10;
  long lookups = 2'000'000;
  int threads = 1;
  double writer_hz = 0.0;
  bool handles = false;
};

struct ReaderResult {
  long lookups = 0;
  long failures = 0;
  double seconds = 0;
  double cpu_seconds = 0;
  double sink = 0;
};

/// One reader: `n` lookups of leaf 0 relative to leaf 1. Interpolated lookups ask for
/// `*query_time` (re-read every 64 lookups: a writer moves time forward).
ReaderResult run_reader(kinematics::FrameReader& r, const BenchTree& t, bool interpolated, long n,
                        const std::atomic<std::int64_t>* query_time, bool handles) {
  ReaderResult out;
  const std::string a = t.leaf1, b = t.leaf0;
  kinematics::Frame fa = *r.frame(a), fb = *r.frame(b);
  std::int64_t tq = query_time->load(std::memory_order_relaxed);
  double sink = 0;
  long failures = 0;
  auto t0 = Clock::now();
  const double cpu0 = thread_cpu_seconds();
  for (long i = 0; i < n; ++i) {
    if ((i & 63) == 0) tq = query_time->load(std::memory_order_relaxed);
    Result<Eigen::Isometry3d> X = handles
                                      ? (interpolated ? r.lookup_at(fa, fb, tq) : r.lookup(fa, fb))
                                      : (interpolated ? r.lookup_at(a, b, tq) : r.lookup(a, b));
    if (X.ok()) {
      sink += X->translation().x();
    } else {
      // With a writer, a reader descheduled for long asks for a time the history has dropped.
      ++failures;
      tq = query_time->load(std::memory_order_relaxed);
    }
  }
  out.seconds = seconds_since(t0);
  out.cpu_seconds = thread_cpu_seconds() - cpu0;
  out.lookups = n;
  out.failures = failures;
  out.sink = sink;
  return out;
}

/// Runs `readers` reader threads for one mode while the calling thread (the graph's owner)
/// writes new samples on every edge at `writer_hz`. Returns aggregate lookups per second.
struct ModeResult {
  double check_x = 0;  ///< x of X_AB from one lookup (static tree): compare with the tf2 bench
  double rate = 0;
  double cpu_rate = 0;  ///< lookups per CPU-second of the readers
  long failures = 0;
  long writes = 0;
};

ModeResult run_mode(const TransformBench& b, bool interpolated, int readers) {
  Graph g(ReplicaId{fnv1a64("bench-transforms"), 1});
  BenchTree t = build_bench_tree(g, b.depth);
  kinematics::FrameTree tree(g);
  std::atomic<std::int64_t> query_time{3 * kSecond / 2};
  ModeResult m;
  {
    auto X = interpolated ? tree.lookup_at(t.leaf1, t.leaf0, 3 * kSecond / 2)
                          : tree.lookup(t.leaf1, t.leaf0);
    if (X.ok()) m.check_x = X->translation().x();
  }
  std::vector<kinematics::FrameReader> rs;
  for (int i = 0; i < readers; ++i) rs.push_back(tree.reader());
  std::vector<ReaderResult> results(readers);
  std::atomic<int> ready{0};
  std::atomic<bool> go{false};
  std::atomic<int> done{0};
  std::vector<std::thread> threads;
  for (int i = 0; i < readers; ++i)
    threads.emplace_back([&, i] {
      ready.fetch_add(1);
      while (!go.load(std::memory_order_acquire)) std::this_thread::yield();
      results[i] = run_reader(rs[i], t, interpolated, b.lookups, &query_time, b.handles);
      rs[i].idle();
      done.fetch_add(1);
    });
  while (ready.load() < readers) std::this_thread::yield();
  go.store(true, std::memory_order_release);
  if (b.writer_hz > 0) {
    // The owner thread: one transaction per tick with a new sample on every edge, 1 ms of
    // replicated time apart; interpolated readers ask for 10 ms ago.
    const auto period = std::chrono::duration_cast<Clock::duration>(
        std::chrono::duration<double>(1.0 / b.writer_hz));
    auto next = Clock::now();
    Rng rng(7);
    std::int64_t stamp = 2 * kSecond;
    while (done.load(std::memory_order_acquire) < readers) {
      next += period;
      std::this_thread::sleep_until(next);
      stamp += kSecond / 1000;
      auto tx = g.begin();
      for (std::size_t e = 0; e < t.child_of.size(); ++e) {
        Pose p = edge_pose(t.edge_index[e].first, t.edge_index[e].second,
                           static_cast<int>(rng.below(2)));
        (void)tx.set_rt(t.parent_of[e], t.child_of[e], p, stamp);
      }
      (void)tx.commit();
      ++m.writes;
      query_time.store(stamp - 10 * kSecond / 1000, std::memory_order_relaxed);
    }
  }
  for (auto& th : threads) th.join();
  long total = 0;
  double sink = 0;
  for (const auto& r : results) {
    total += r.lookups;
    m.failures += r.failures;
    sink += r.sink;
  }
  if (sink == 12345.678) std::fprintf(stderr, " ");  // keep the results alive
  // Aggregate rate: all lookups over the time the slowest reader took.
  double slowest = 0, cpu = 0;
  for (const auto& r : results) {
    slowest = std::max(slowest, r.seconds);
    cpu += r.cpu_seconds;
  }
  m.rate = total / std::max(slowest, 1e-9);
  m.cpu_rate = total / std::max(cpu, 1e-9);
  return m;
}

void run_transform_bench(const TransformBench& b) {
  for (bool interpolated : {false, true}) {
    nlohmann::json j;
    j["mode"] = interpolated ? "interpolated" : "latest";
    j["depth"] = b.depth;
    ModeResult m = run_mode(b, interpolated, b.threads);
    j["lookups_per_s"] = static_cast<long>(m.rate);
    j["lookups_per_cpu_s"] = static_cast<long>(m.cpu_rate);
    j["check_x"] = round_to(m.check_x, 9);
    if (b.threads > 1 || b.writer_hz > 0) {
      j["threads"] = b.threads;
      j["writer_hz"] = b.writer_hz;
      j["writes"] = m.writes;
      if (b.threads > 1) {
        ModeResult one = run_mode(b, interpolated, 1);
        j["one_reader_lookups_per_s"] = static_cast<long>(one.rate);
        j["scaling"] = round_to(m.rate / one.rate, 2);
      }
    }
    if (b.handles) j["handles"] = true;
    if (m.failures) {
      j["failures"] = m.failures;
      if (b.writer_hz == 0) set_exit_code(1);  // a static tree answers every lookup
    }
    std::cout << j.dump() << std::endl;
  }
}

// ---------------------------------------------------------------------------- bench scene

struct SceneBench {
  std::vector<int> objects{100, 1000, 10000, 100000};
  int moves = 20000;
};

/// Cost of moving one object in an n-object scene (one graph transaction per move, the scene
/// following the graph): should grow like log n, not like n.
void run_scene_bench(const SceneBench& b) {
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
  auto ia = std::make_shared<ImportArgs>();
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
  auto tb = std::make_shared<TransformBench>();
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
  tr->callback([tb] { run_transform_bench(*tb); });

  auto sb = std::make_shared<SceneBench>();
  auto* sc = bench->add_subcommand(
      "scene", "Cost of one moved object's update in the FCL scene, for growing scenes");
  sc->add_option("--objects", sb->objects, "scene sizes")->check(CLI::Range(1, 10'000'000))->capture_default_str();
  sc->add_option("--moves", sb->moves, "moves per size")
      ->check(CLI::Range(1, 100'000'000))
      ->capture_default_str();
  sc->callback([sb] { run_scene_bench(*sb); });
}

}  // namespace quiver::tools
