#pragma once
// The transform lookup benchmark (`quiver bench transforms`): lookups on the two-branch tree that
// quiver_bench_tf2 runs against tf2, latest and interpolated, with reader threads and a writer.

namespace quiver::tools::bench {

struct TransformBench {
  int depth = 10;            ///< frames per branch
  long lookups = 2'000'000;  ///< lookups per reader and mode
  int threads = 1;           ///< reader threads
  double writer_hz = 0.0;    ///< a writer commits a new sample on every edge at this rate (0: none)
  bool handles = false;      ///< look up by pre-resolved frame handles instead of names
};

/// Looks up the leaf of branch 0 relative to the leaf of branch 1 of the benchmark tree
/// (bench_pose()), at the latest time and interpolated. Prints one JSON line per mode on stdout
/// (lookups per second and per CPU-second, the result's x to compare with tf2; with threads or a
/// writer, the scaling against one reader).
/// @pre b.depth, b.lookups and b.threads are at least 1; b.writer_hz >= 0.
/// @returns the exit status: 0, or 1 when a lookup failed on a static tree (no writer).
int run_transform_bench(const TransformBench& b);

}  // namespace quiver::tools::bench
