// The CRDT core benchmark (`quiver bench crdt`): random writes, encode, decode and apply.
#include "quiver/tools/bench/crdt_bench.h"

#include <chrono>
#include <iostream>
#include <nlohmann/json.hpp>

#include "quiver/agents/runtime/process/logging.h"
#include "quiver/base/rng.h"
#include "quiver/graph/codec.h"
#include "quiver/graph/graph.h"
#include "quiver/base/percentiles.h"
#include "quiver/tools/bench/bench_objects.h"
#include "quiver/tools/bench/bench_util.h"

namespace quiver::tools::bench {

int run_crdt_bench(const CrdtBench& b) {
  using namespace graph;
  using Clock = std::chrono::steady_clock;
  Graph a(ReplicaId{0xA, 1});
  Graph r(ReplicaId{0xB, 1});
  std::vector<std::vector<std::uint8_t>> deltas;
  std::size_t total_bytes = 0;
  bool measuring = false;
  a.set_delta_sink([&](const GraphDelta& d) {
    std::vector<std::uint8_t> bytes;
    encode(d, bytes);
    if (measuring) total_bytes += bytes.size();
    deltas.push_back(std::move(bytes));
  });
  auto objects = create_bench_objects(a, b.nodes, b.attrs);
  if (!objects.ok()) {
    agents::named_logger("quiver bench crdt")->error("{}", objects.error().to_string());
    return 2;
  }
  const std::vector<Symbol>& names = objects->attrs;
  const std::vector<NodeId>& ids = objects->ids;
  std::size_t setup_msgs = deltas.size();
  Rng rng(b.seed);
  measuring = true;
  long done = 0;
  auto t0 = Clock::now();
  while (done < b.updates) {
    auto tx = a.begin();
    long n = std::min<long>(b.batch, b.updates - done);
    for (long i = 0; i < n; ++i) {
      (void)tx.set(ids[rng.below(ids.size())], names[rng.below(names.size())],
                   Value(rng.uniform()));
    }
    (void)tx.commit();
    done += n;
  }
  double local_s = seconds_since(t0);
  if (b.events) r.subscribe([](const ChangeBatch&) {});
  GraphDelta scratch;
  for (std::size_t i = 0; i < setup_msgs; ++i) {
    (void)decode(deltas[i], scratch);
    r.merge(scratch);
  }
  auto t1 = Clock::now();
  for (std::size_t i = setup_msgs; i < deltas.size(); ++i) {
    Status s = decode(deltas[i], scratch);
    if (!s.ok()) {
      agents::named_logger("quiver bench crdt")->error("decode failed: {}", s.error().to_string());
      return 2;
    }
    r.merge(scratch);
  }
  double remote_s = seconds_since(t1);
  std::vector<std::uint8_t> state = encode(r.state());
  bool same = a.digest() == r.digest();
  nlohmann::json j;
  j["bench"] = "crdt";
  j["nodes"] = b.nodes;
  j["attrs"] = b.attrs;
  j["updates"] = b.updates;
  j["batch"] = b.batch;
  j["local_ops_per_s"] = static_cast<long>(b.updates / local_s);
  j["remote_apply_ops_per_s"] = static_cast<long>(b.updates / remote_s);
  j["bytes_per_update"] = round_to(static_cast<double>(total_bytes) / b.updates, 2);
  j["state_bytes"] = state.size();
  j["replicas_equal"] = same;
  if (b.events) j["events"] = true;
  std::cout << j.dump() << std::endl;
  return same ? 0 : 1;
}

}  // namespace quiver::tools::bench
