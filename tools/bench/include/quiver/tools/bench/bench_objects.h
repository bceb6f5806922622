#pragma once
// The world the graph benchmarks write to: N "object" nodes with A numeric attributes each.
#include <vector>

#include "quiver/base/result.h"
#include "quiver/graph/graph.h"

namespace quiver::tools::bench {

struct BenchObjects {
  std::vector<graph::Symbol> attrs;  ///< a0 .. a{A-1}
  std::vector<graph::NodeId> ids;    ///< n0 .. n{N-1}
};

/// Creates `nodes` nodes of type "object" named n0.. in `g`, each with the attributes a0..
/// (`attrs` of them) set to 0.0, in one transaction. @returns their ids and the attributes'
/// names, or the commit's error.
Result<BenchObjects> create_bench_objects(graph::Graph& g, int nodes, int attrs);

}  // namespace quiver::tools::bench
