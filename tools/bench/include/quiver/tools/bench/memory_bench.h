#pragma once
// What a replica holds per node, attribute and edge (`quiver bench memory`): heap bytes measured
// with glibc's mallinfo2() around building a graph, beside the payload those bytes carry. The
// default node is CORTEX's representative one (its LWW_ANALYSIS.md: 10 attributes, 3 edges of 2
// attributes each; ~7.6 KB per node in DSR's CRDT for ~0.8 KB of payload).

#include <cstdint>

namespace quiver::tools::bench {

struct MemoryBench {
  int nodes = 10'000;
  int attrs = 10;       ///< per node
  int edges = 3;        ///< per node (to other nodes)
  int edge_attrs = 2;   ///< per edge
  int runs = 3;         ///< medians over this many builds are reported
  std::uint64_t seed = 1;
};

/// Builds graphs of `nodes` nodes (none, the attributes, the edges, each alone and all together),
/// committed in transactions of 100 nodes, and prints one JSON line: heap bytes per node, per
/// attribute and per edge, the payload per node (names and values), and their ratio.
/// @pre every count >= 0, nodes >= 2 when edges > 0, runs >= 1.
/// @returns 0, or 2 when a graph cannot be built.
int run_memory_bench(const MemoryBench& b);

}  // namespace quiver::tools::bench
