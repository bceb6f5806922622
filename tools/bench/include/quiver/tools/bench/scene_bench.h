#pragma once
// The collision scene benchmark (`quiver bench scene`): what one moved object's update costs in
// the FCL scene that follows the graph, for growing scenes.

#include <vector>

namespace quiver::tools::bench {

struct SceneBench {
  std::vector<int> objects{100, 1000, 10000, 100000};  ///< scene sizes
  int moves = 20000;                                   ///< moves per size
};

/// For each size n: n spheres under "world", then `moves` random walk steps of one object per
/// transaction, the scene following the graph. Prints one JSON line per size on stdout (build
/// time, the scene's update per move and the whole move's, objects updated, full rebuilds): the
/// update should grow like log n, not like n.
/// @pre every size and b.moves are at least 1.
/// @returns the exit status: 0.
int run_scene_bench(const SceneBench& b);

}  // namespace quiver::tools::bench
