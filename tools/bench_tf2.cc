// quiver_bench_tf2: the `quiver bench transforms` workload run against ROS tf2 (Debian
// libtf2-dev), printing the same JSON lines with "impl":"tf2", so both run on one machine in one
// go. The tree (the poses come from bench_util.h, as in tools/bench/src/transform_bench.cc): root
// "world", two branches b0_1..b0_D and b1_1..b1_D, each edge with a sample at t = 1 s and one at
// t = 2 s; look up the leaf of branch 0 relative to the leaf of branch 1 at the latest time and
// at t = 1.5 s.
//
// Usage: quiver_bench_tf2 [--depth D] [--lookups N] [--threads K]

#include <tf2/buffer_core.h>
#include <tf2/exceptions.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "quiver/tools/bench/bench_util.h"

namespace {

using Clock = std::chrono::steady_clock;
using quiver::tools::bench::bench_pose;
using quiver::tools::bench::BenchPose;
using quiver::tools::bench::seconds_since;

void build(tf2::BufferCore& buf, int depth) {
  for (int sample = 0; sample < 2; ++sample)
    for (int k = 0; k < 2; ++k) {
      std::string parent = "world";
      for (int i = 1; i <= depth; ++i) {
        const std::string child = "b" + std::to_string(k) + "_" + std::to_string(i);
        const BenchPose p = bench_pose(k, i, sample);
        geometry_msgs::TransformStamped ts;
        ts.header.stamp = ros::Time(sample + 1.0);
        ts.header.frame_id = parent;
        ts.child_frame_id = child;
        ts.transform.translation.x = p.translation[0];
        ts.transform.translation.y = p.translation[1];
        ts.transform.translation.z = p.translation[2];
        ts.transform.rotation.w = p.rotation[0];
        ts.transform.rotation.x = p.rotation[1];
        ts.transform.rotation.y = p.rotation[2];
        ts.transform.rotation.z = p.rotation[3];
        buf.setTransform(ts, "bench");
        parent = child;
      }
    }
}

double run(tf2::BufferCore& buf, int depth, bool interpolated, long n, long* failures) {
  const std::string a = "b1_" + std::to_string(depth), b = "b0_" + std::to_string(depth);
  const ros::Time t = interpolated ? ros::Time(1.5) : ros::Time(0);
  double sink = 0;
  for (long i = 0; i < n; ++i) {
    try {
      sink += buf.lookupTransform(a, b, t).transform.translation.x;
    } catch (const tf2::TransformException& e) {
      if (++*failures == 1) std::fprintf(stderr, "tf2: %s\n", e.what());
    }
  }
  return sink;
}

}  // namespace

int main(int argc, char** argv) {
  int depth = 10;
  long lookups = 2'000'000;
  int threads = 1;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--depth"))
      depth = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--lookups"))
      lookups = std::atol(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--threads"))
      threads = std::atoi(argv[i + 1]);
    else {
      std::fprintf(stderr, "usage: quiver_bench_tf2 [--depth D] [--lookups N] [--threads K]\n");
      return 2;
    }
  }
  if (depth < 1 || lookups < 1 || threads < 1) return 2;
  ros::Time::init();
  int status = 0;
  for (bool interpolated : {false, true}) {
    tf2::BufferCore buf(ros::Duration(100.0));
    build(buf, depth);
    const double check_x =
        buf.lookupTransform("b1_" + std::to_string(depth), "b0_" + std::to_string(depth),
                            interpolated ? ros::Time(1.5) : ros::Time(0))
            .transform.translation.x;
    std::vector<long> failures(threads, 0);
    std::vector<double> seconds(threads, 0);
    std::vector<std::thread> ts;
    std::atomic<bool> go{false};
    for (int k = 0; k < threads; ++k)
      ts.emplace_back([&, k] {
        while (!go.load()) std::this_thread::yield();
        auto t0 = Clock::now();
        volatile double sink = run(buf, depth, interpolated, lookups, &failures[k]);
        (void)sink;
        seconds[k] = seconds_since(t0);
      });
    go.store(true);
    for (auto& t : ts) t.join();
    double slowest = 0;
    long failed = 0;
    for (int k = 0; k < threads; ++k) {
      slowest = std::max(slowest, seconds[k]);
      failed += failures[k];
    }
    const long rate = static_cast<long>(static_cast<double>(lookups) * threads / slowest);
    std::printf("{\"impl\":\"tf2\",\"mode\":\"%s\",\"depth\":%d,\"lookups_per_s\":%ld",
                interpolated ? "interpolated" : "latest", depth, rate);
    std::printf(",\"check_x\":%.9f", check_x);
    if (threads > 1) std::printf(",\"threads\":%d", threads);
    if (failed) {
      std::printf(",\"failures\":%ld", failed);
      status = 1;
    }
    std::printf("}\n");
  }
  return status;
}
