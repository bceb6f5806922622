// quiver bench memory: heap bytes per node, attribute and edge of a replica, measured around
// building graphs, beside the payload they carry.
#include "quiver/tools/bench/memory_bench.h"

#include <malloc.h>

#include <algorithm>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "quiver/base/percentiles.h"
#include "quiver/base/rng.h"
#include "quiver/graph/graph.h"

namespace quiver::tools::bench {
namespace {

using graph::NodeId;
using graph::Value;

std::size_t heap_in_use() { return mallinfo2().uordblks; }

struct Built {
  std::size_t bytes = 0;    // heap the graph holds
  std::size_t payload = 0;  // names and values it was given
  bool ok = true;
};

// A value about as large as a DSR attribute's: doubles, short strings, small float vectors.
Value value_for(int k, Rng& rng) {
  switch (k % 3) {
    case 0: return Value(rng.uniform());
    case 1: return Value("value " + std::to_string(rng.below(100000)));
    default: return Value(graph::Vec3f{static_cast<float>(rng.uniform()), 1.0f, 2.0f});
  }
}

Built build(const MemoryBench& b, bool attrs, bool edges, std::uint64_t seed) {
  Built out;
  Rng rng(seed);
  std::vector<std::string> attr_names, edge_attr_names;
  for (int k = 0; k < b.attrs; ++k) attr_names.push_back("attribute_" + std::to_string(k));
  for (int k = 0; k < b.edge_attrs; ++k) edge_attr_names.push_back("edge_attribute_" + std::to_string(k));
  const std::size_t before = heap_in_use();
  auto g = std::make_unique<graph::Graph>(graph::ReplicaId{1, 1});
  std::vector<NodeId> ids;
  for (int first = 0; first < b.nodes && out.ok; first += 100) {
    auto tx = g->begin();
    for (int i = first; i < std::min(b.nodes, first + 100); ++i) {
      const std::string name = "node_" + std::to_string(i);
      auto id = tx.create_node("object", name);
      if (!id.ok()) {
        out.ok = false;
        break;
      }
      ids.push_back(*id);
      out.payload += name.size() + 6;
      for (int k = 0; attrs && k < b.attrs; ++k) {
        Value v = value_for(k, rng);
        out.payload += attr_names[k].size() + v.payload_bytes();
        out.ok = out.ok && tx.set(*id, attr_names[k], std::move(v)).ok();
      }
    }
    out.ok = out.ok && tx.commit().ok();
  }
  for (int first = 0; edges && first < b.nodes && out.ok; first += 100) {
    auto tx = g->begin();
    for (int i = first; i < std::min(b.nodes, first + 100); ++i)
      for (int e = 1; e <= b.edges; ++e) {
        std::vector<std::pair<graph::Symbol, Value>> ea;
        for (int k = 0; k < b.edge_attrs; ++k) {
          Value v = value_for(k, rng);
          out.payload += edge_attr_names[k].size() + v.payload_bytes();
          ea.emplace_back(graph::Symbol(edge_attr_names[k]), std::move(v));
        }
        out.payload += 2 * 8 + 4;  // two ends and a type
        out.ok = out.ok && tx.insert_edge(ids[i], ids[(i + e) % ids.size()], "link_" + std::to_string(e), std::move(ea)).ok();
      }
    out.ok = out.ok && tx.commit().ok();
  }
  malloc_trim(0);
  out.bytes = heap_in_use() - before;
  return out;
}


}  // namespace

int run_memory_bench(const MemoryBench& b) {
  std::vector<double> bare, with_attrs, with_edges, all, payload;
  for (int r = 0; r < b.runs; ++r) {
    const std::uint64_t seed = b.seed + static_cast<std::uint64_t>(r);
    const Built n0 = build(b, false, false, seed), na = build(b, true, false, seed),
                ne = build(b, false, true, seed), nall = build(b, true, true, seed);
    if (!n0.ok || !na.ok || !ne.ok || !nall.ok) {
      std::fprintf(stderr, "quiver bench memory: a graph could not be built\n");
      return 2;
    }
    bare.push_back(static_cast<double>(n0.bytes));
    with_attrs.push_back(static_cast<double>(na.bytes));
    with_edges.push_back(static_cast<double>(ne.bytes));
    all.push_back(static_cast<double>(nall.bytes));
    payload.push_back(static_cast<double>(nall.payload));
  }
  const double n = b.nodes;
  nlohmann::json j;
  j["bench"] = "memory";
  j["nodes"] = b.nodes;
  j["attrs_per_node"] = b.attrs;
  j["edges_per_node"] = b.edges;
  j["attrs_per_edge"] = b.edge_attrs;
  j["bytes_per_node"] = median(all) / n;  // everything: the node, its attributes, its edges
  j["bytes_per_bare_node"] = median(bare) / n;
  j["bytes_per_attribute"] = b.attrs > 0 ? (median(with_attrs) - median(bare)) / (n * b.attrs) : 0.0;
  j["bytes_per_edge"] = b.edges > 0 ? (median(with_edges) - median(bare)) / (n * b.edges) : 0.0;  // with its attributes
  j["payload_bytes_per_node"] = median(payload) / n;
  j["overhead_ratio"] = median(all) / median(payload);
  j["runs"] = b.runs;
  std::printf("%s\n", j.dump().c_str());
  return 0;
}

}  // namespace quiver::tools::bench
