#pragma once
// The benchmarks' clock and the `bench transforms` tree, shared with quiver_bench_tf2 (built as
// C++17 against tf2, without the quiver libraries: this header needs only the standard library
// and Eigen).

#include <Eigen/Geometry>
#include <array>
#include <chrono>

namespace quiver::tools::bench {

/// @returns the seconds of steady_clock time since `t0`.
inline double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// One edge pose of the `bench transforms` tree: root "world", two branches b0_1..b0_D and
/// b1_1..b1_D; edge i of branch k has a pose at t = 1 s (sample 0) and another at t = 2 s
/// (sample 1), with different rotations and translations.
struct BenchPose {
  std::array<double, 3> translation;
  std::array<double, 4> rotation;  // w x y z
};

/// @returns the pose of edge `i` of branch `branch` (0 or 1) at sample `sample` (0 or 1).
inline BenchPose bench_pose(int branch, int i, int sample) {
  const double angle = 0.1 * (i + 1) + 0.05 * branch + 0.3 * sample;
  Eigen::Vector3d axis(1.0 + 0.1 * i, 0.5 * branch - 0.2, 0.3 + 0.2 * sample);
  axis.normalize();
  Eigen::Quaterniond q(Eigen::AngleAxisd(angle, axis));
  return BenchPose{{0.1 + 0.01 * i + 0.05 * sample, 0.02 * branch - 0.01, 0.05 + 0.001 * i},
                   {q.w(), q.x(), q.y(), q.z()}};
}

}  // namespace quiver::tools::bench
