// The world the graph benchmarks write to: N "object" nodes with A numeric attributes each.
#include "quiver/tools/bench/bench_objects.h"

#include <string>
#include <utility>

namespace quiver::tools::bench {

Result<BenchObjects> create_bench_objects(graph::Graph& g, int nodes, int attrs) {
  BenchObjects out;
  for (int k = 0; k < attrs; ++k) out.attrs.emplace_back("a" + std::to_string(k));
  auto tx = g.begin();
  for (int i = 0; i < nodes; ++i) {
    std::vector<std::pair<graph::Symbol, graph::Value>> init;
    for (int k = 0; k < attrs; ++k) init.emplace_back(out.attrs[k], graph::Value(0.0));
    auto id = tx.create_node("object", "n" + std::to_string(i), std::move(init));
    if (!id.ok()) return id.error();
    out.ids.push_back(*id);
  }
  if (auto c = tx.commit(); !c.ok()) return c.error();
  return out;
}

}  // namespace quiver::tools::bench
