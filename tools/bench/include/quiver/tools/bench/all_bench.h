#pragma once
// `quiver bench all`: every benchmark beside its peer, measured in one run (ddsperf for DDS, Yjs
// through node for the CRDT where node and Debian's node-yjs are installed, tf2 for transforms),
// written as one JSON file and one page of plots (docs/performance.md).

#include <cstdint>
#include <string>

namespace quiver::tools::bench {

struct AllBench {
  std::string quiver;  ///< the quiver executable (quiver_bench_tf2 beside it)
  std::string out;     ///< the report's folder (default: a new /tmp/quiver-bench-all-*)
  bool quick = false;  ///< small sizes: a check that everything runs, not figures to quote
  std::uint32_t domain = 86;  ///< DDS domain of the DDS benchmarks and of ddsperf (loopback)
};

/// Runs each benchmark and peer in turn and writes OUT/bench.json (each command, its seconds, exit
/// status and JSON lines, and a summary of Quiver against each peer), then OUT/index.html with
/// its plots as SVG and PNG (python3-matplotlib; without it the page says so). A peer that is not
/// installed is listed as absent with the reason. Prints the summary as JSON lines.
/// @returns 0 when every command ran and exited 0 (absent peers aside), 1 otherwise, 2 when the
/// report cannot be written.
int run_all_bench(const AllBench& b);

}  // namespace quiver::tools::bench
