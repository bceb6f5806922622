// quiver bench ...: benchmarks that print one JSON line per result.

#include <chrono>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "bench_stats.h"
#include "bench_util.h"
#include "commands.h"
#include "quiver/agents/runtime/process/logging.h"
#include "quiver/graph/codec.h"
#include "quiver/graph/graph.h"
#include "quiver/graph/world_file.h"
#include "quiver/base/rng.h"

namespace quiver::tools {
namespace {

using Clock = std::chrono::steady_clock;

struct CrdtBench {
  int nodes = 1000;
  int attrs = 10;
  long updates = 1'000'000;
  int batch = 100;
  std::uint64_t seed = 1;
  bool events = false;
};

// The workload we also run against Yjs and Automerge: replica A holds nodes × attrs doubles and
// performs random writes in transactions of `batch`; every transaction's delta is encoded. Replica
// B then decodes and applies every delta.
void run_crdt_bench(const CrdtBench& b) {
  using namespace graph;
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
  std::vector<Symbol> names;
  for (int k = 0; k < b.attrs; ++k) names.emplace_back("a" + std::to_string(k));
  std::vector<NodeId> ids;
  {
    auto tx = a.begin();
    for (int i = 0; i < b.nodes; ++i) {
      std::vector<std::pair<Symbol, Value>> init;
      for (int k = 0; k < b.attrs; ++k) init.emplace_back(names[k], Value(0.0));
      ids.push_back(*tx.create_node("object", "n" + std::to_string(i), std::move(init)));
    }
    (void)tx.commit();
  }
  std::size_t setup_msgs = deltas.size();
  Rng rng(b.seed);
  measuring = true;
  long done = 0;
  auto t0 = Clock::now();
  while (done < b.updates) {
    auto tx = a.begin();
    long n = std::min<long>(b.batch, b.updates - done);
    for (long i = 0; i < n; ++i) {
      (void)tx.set(ids[rng.below(ids.size())], names[rng.below(names.size())], Value(rng.uniform()));
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
      set_exit_code(2);
      return;
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
  if (!same) set_exit_code(1);
}

struct LoadBench {
  int frames = 100'000;
  int runs = 5;
};

// One transaction that builds an RT chain of `frames` frames (each a new node under the last),
// committed and encoded; a second replica decodes and merges it; then the same chain as a JSON
// world file is loaded into a third. Medians over runs, in milliseconds.
void run_load_bench(const LoadBench& b) {
  using namespace graph;
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
        rts.push_back({{"parent", "f" + std::to_string(i - 1)}, {"child", "f" + std::to_string(i)},
                       {"translation", {0.01, 0, 0}}, {"rotation", {1, 0, 0, 0}}});
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
        set_exit_code(2);
        return;
      }
      prev = n;
    }
    build_ms.push_back(seconds_since(t0) * 1e3);
    auto t1 = Clock::now();
    auto c = tx.commit();
    commit_ms.push_back(seconds_since(t1) * 1e3);
    if (!c.ok()) {
      agents::named_logger("quiver bench load")->error("{}", c.error().to_string());
      set_exit_code(2);
      return;
    }
    bytes = delta.size();
    auto t2 = Clock::now();
    auto d = decode(delta);
    if (d.ok()) r.merge(*d);
    merge_ms.push_back(seconds_since(t2) * 1e3);
    same = same && d.ok() && r.digest() == a.digest() && r.rt_parent(*r.find_node("f1")).has_value();
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
  if (!same) set_exit_code(1);
}

}  // namespace

void add_bench_commands(CLI::App& app) {
  auto* bench = app.add_subcommand("bench", "Benchmarks (one JSON line per result)");
  auto b = std::make_shared<CrdtBench>();
  auto* crdt = bench->add_subcommand("crdt", "CRDT core: random attribute writes, encode, decode and apply");
  crdt->add_option("--nodes", b->nodes)->check(CLI::Range(1, 10'000'000))->capture_default_str();
  crdt->add_option("--attrs", b->attrs)->check(CLI::Range(1, 1000))->capture_default_str();
  crdt->add_option("--updates", b->updates)->check(CLI::Range(1L, 1'000'000'000L))->capture_default_str();
  crdt->add_option("--batch", b->batch)->check(CLI::Range(1, 1'000'000))->capture_default_str();
  crdt->add_option("--seed", b->seed)->check(CLI::NonNegativeNumber)->capture_default_str();
  crdt->add_flag("--events", b->events, "subscribe to change events on the receiving replica");
  crdt->callback([b] { run_crdt_bench(*b); });
  auto l = std::make_shared<LoadBench>();
  auto* load = bench->add_subcommand("load", "One large transaction: an RT chain built, committed, decoded and merged; "
                                             "and the same chain loaded from a world file");
  load->add_option("--frames", l->frames)->check(CLI::Range(2, 10'000'000))->capture_default_str();
  load->add_option("--runs", l->runs)->check(CLI::Range(1, 1000))->capture_default_str();
  load->callback([l] { run_load_bench(*l); });
}

}  // namespace quiver::tools
