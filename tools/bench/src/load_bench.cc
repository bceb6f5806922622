// The large-transaction benchmark (`quiver bench load`): one RT chain as a transaction, a merged
// delta and a world file.
#include "quiver/tools/bench/load_bench.h"

#include <chrono>
#include <iostream>
#include <nlohmann/json.hpp>

#include "quiver/agents/runtime/process/logging.h"
#include "quiver/graph/codec.h"
#include "quiver/graph/graph.h"
#include "quiver/graph/world_file.h"
#include "quiver/base/percentiles.h"
#include "quiver/tools/bench/bench_util.h"

namespace quiver::tools::bench {

int run_load_bench(const LoadBench& b) {
  using namespace graph;
  using Clock = std::chrono::steady_clock;
  std::vector<double> build_ms, commit_ms, merge_ms, world_ms;
  std::size_t bytes = 0;
  bool same = true;
  std::string world;
  {
    nlohmann::json w;
    w["quiver_world"] = 1;
    nlohmann::json nodes = nlohmann::json::array(), rts = nlohmann::json::array();
    for (int i = 0; i < b.frames; ++i) {
      nodes.push_back({{"name", "f" + std::to_string(i)}, {"type", "frame"}});
      if (i > 0)
        rts.push_back({{"parent", "f" + std::to_string(i - 1)},
                       {"child", "f" + std::to_string(i)},
                       {"translation", {0.01, 0, 0}},
                       {"rotation", {1, 0, 0, 0}}});
    }
    w["nodes"] = std::move(nodes);
    w["rt"] = std::move(rts);
    world = w.dump();
  }
  for (int run = 0; run < b.runs; ++run) {
    Graph a(ReplicaId{0xA, 1}), r(ReplicaId{0xB, 1}), wg(ReplicaId{0xC, 1});
    std::vector<std::uint8_t> delta;
    a.set_delta_sink([&](const GraphDelta& d) { encode(d, delta); });
    auto t0 = Clock::now();
    auto tx = a.begin();
    NodeId prev = *tx.create_node("frame", "f0");
    Pose step;
    step.translation = {0.01, 0, 0};
    for (int i = 1; i < b.frames; ++i) {
      NodeId n = *tx.create_node("frame", "f" + std::to_string(i));
      if (!tx.set_rt(prev, n, step, 0).ok()) {
        agents::named_logger("quiver bench load")->error("set_rt refused at frame {}", i);
        return 2;
      }
      prev = n;
    }
    build_ms.push_back(seconds_since(t0) * 1e3);
    auto t1 = Clock::now();
    auto c = tx.commit();
    commit_ms.push_back(seconds_since(t1) * 1e3);
    if (!c.ok()) {
      agents::named_logger("quiver bench load")->error("{}", c.error().to_string());
      return 2;
    }
    bytes = delta.size();
    auto t2 = Clock::now();
    auto d = decode(delta);
    if (d.ok()) r.merge(*d);
    merge_ms.push_back(seconds_since(t2) * 1e3);
    same =
        same && d.ok() && r.digest() == a.digest() && r.rt_parent(*r.find_node("f1")).has_value();
    auto t3 = Clock::now();
    auto loaded = load_world(wg, world, "chain.json");
    world_ms.push_back(seconds_since(t3) * 1e3);
    same = same && loaded.ok() && wg.node_count() == static_cast<std::size_t>(b.frames);
  }
  auto med = [](std::vector<double> v) { return round_to(Percentiles(std::move(v)).at(0.5), 1); };
  nlohmann::json j;
  j["bench"] = "load";
  j["frames"] = b.frames;
  j["runs"] = b.runs;
  j["build_ms"] = med(build_ms);
  j["commit_ms"] = med(commit_ms);
  j["transaction_ms"] = med([&] {
    std::vector<double> t;
    for (std::size_t i = 0; i < build_ms.size(); ++i) t.push_back(build_ms[i] + commit_ms[i]);
    return t;
  }());
  j["decode_merge_ms"] = med(merge_ms);
  j["world_file_ms"] = med(world_ms);
  j["delta_bytes"] = bytes;
  j["replicas_equal"] = same;
  std::cout << j.dump() << std::endl;
  return same ? 0 : 1;
}

}  // namespace quiver::tools::bench
