// The transform lookup benchmark (`quiver bench transforms`): reader threads looking up the
// two-branch tree, latest and interpolated, while a writer may move it.
#include "quiver/tools/bench/transform_bench.h"

#include <time.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

#include "quiver/base/hash.h"
#include "quiver/base/rng.h"
#include "quiver/graph/graph.h"
#include "quiver/kinematics/frames.h"
#include "quiver/base/percentiles.h"
#include "quiver/tools/bench/bench_util.h"

namespace quiver::tools::bench {
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

}  // namespace

int run_transform_bench(const TransformBench& b) {
  int status = 0;
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
      if (b.writer_hz == 0) status = 1;  // a static tree answers every lookup
    }
    std::cout << j.dump() << std::endl;
  }
  return status;
}

}  // namespace quiver::tools::bench
