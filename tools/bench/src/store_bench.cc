// The durable store benchmark (`quiver bench store`): write rates per durability and the reload
// of a large replica from its log and from a snapshot.
#include "quiver/tools/bench/store_bench.h"

#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>

#include "quiver/agents/replica/store/store.h"
#include "quiver/agents/runtime/process/logging.h"
#include "quiver/base/hash.h"
#include "quiver/base/rng.h"
#include "quiver/graph/codec.h"
#include "quiver/graph/graph.h"
#include "quiver/base/percentiles.h"
#include "quiver/tools/bench/bench_objects.h"
#include "quiver/tools/bench/bench_util.h"

namespace quiver::tools::bench {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using agents::Durability;
using agents::Store;
using agents::StoreOptions;

fs::path fresh_dir(const fs::path& base, const std::string& name) {
  fs::path p = base / name;
  fs::remove_all(p);
  return p;
}

Result<std::unique_ptr<Store>> open_store(const fs::path& dir, Durability d) {
  StoreOptions o;
  o.dir = dir.string();
  o.durability = d;
  return Store::open(o, "bench", 1);
}

// One run of the write workload; `store` may be null. Returns local ops/s and the flush time.
struct WriteRun {
  double ops_per_s = 0;
  double flush_ms = 0;
};

Result<WriteRun> write_run(const StoreBench& b, Store* store, std::uint64_t seed) {
  using namespace graph;
  Graph a(ReplicaId{fnv1a64("bench"), 1});
  std::uint64_t seq = 0;
  std::vector<std::uint8_t> bytes;
  a.set_delta_sink([&](const GraphDelta& d) {
    bytes.clear();
    encode(d, bytes, seq + 1, seq + 1);
    ++seq;
    if (store != nullptr) store->local(seq, bytes);
  });
  auto objects = create_bench_objects(a, b.nodes, b.attrs);
  if (!objects.ok()) return objects.error();
  const std::vector<Symbol>& names = objects->attrs;
  const std::vector<NodeId>& ids = objects->ids;
  Rng rng(seed);
  long done = 0;
  const auto t0 = Clock::now();
  while (done < b.updates) {
    auto tx = a.begin();
    const long n = std::min<long>(b.batch, b.updates - done);
    for (long i = 0; i < n; ++i)
      (void)tx.set(ids[rng.below(ids.size())], names[rng.below(names.size())],
                   Value(rng.uniform()));
    (void)tx.commit();
    done += n;
  }
  WriteRun r;
  r.ops_per_s = b.updates / seconds_since(t0);
  if (store != nullptr) {
    const auto t1 = Clock::now();
    if (Status s = store->sync(); !s.ok()) return s.error();
    r.flush_ms = seconds_since(t1) * 1e3;
  }
  return r;
}

// A replica of `n` nodes (4 attributes each, an edge to the previous node), built in
// transactions of 1000 nodes whose deltas go to `store`.
Status build_replica(int n, Store& store) {
  using namespace graph;
  Graph g(ReplicaId{fnv1a64("bench"), 1});
  std::uint64_t seq = 0;
  g.set_delta_sink([&](const GraphDelta& d) {
    std::vector<std::uint8_t> bytes;
    encode(d, bytes, seq + 1, seq + 1);
    store.local(++seq, bytes);
  });
  NodeId prev{};
  for (int i = 0; i < n;) {
    auto tx = g.begin();
    for (int k = 0; k < 1000 && i < n; ++k, ++i) {
      auto id = tx.create_node("object", "n" + std::to_string(i),
                               {{Symbol("x"), Value(double(i))},
                                {Symbol("y"), Value(double(-i))},
                                {Symbol("label"), Value("object " + std::to_string(i))},
                                {Symbol("seen"), Value(std::int64_t{i})}});
      if (!id.ok()) return id.error();
      if (i > 0)
        if (Status s = tx.insert_edge(prev, *id, "next"); !s.ok()) return s;
      prev = *id;
    }
    if (auto c = tx.commit(); !c.ok()) return c.error();
  }
  return store.sync();
}

Result<double> reload_ms(const fs::path& dir, std::size_t& nodes) {
  const auto t0 = Clock::now();
  auto s = open_store(dir, Durability::kBatch);
  if (!s.ok()) return s.error();
  graph::Graph g(graph::ReplicaId{fnv1a64("bench"), (*s)->opening().incarnation});
  auto applied = (*s)->load(g);
  if (!applied.ok()) return applied.error();
  const double ms = seconds_since(t0) * 1e3;
  nodes = g.node_count();
  return ms;
}

}  // namespace

int run_store_bench(const StoreBench& b) {
  auto log = agents::named_logger("quiver bench store");
  const fs::path base = b.dir.empty() ? fs::temp_directory_path() /
                                            ("quiver-bench-store-" + std::to_string(::getpid()))
                                      : fs::path(b.dir);
  fs::create_directories(base);
  struct Cleanup {
    fs::path p;
    bool own;
    ~Cleanup() {
      std::error_code ec;
      if (own) fs::remove_all(p, ec);
    }
  } cleanup{base, b.dir.empty()};

  // Writes: the modes alternate within each round, so a noisy machine hits them alike.
  const std::vector<std::pair<std::string, std::optional<Durability>>> modes = {
      {"memory", std::nullopt},
      {"none", Durability::kNone},
      {"batch", Durability::kBatch},
      {"always", Durability::kAlways}};
  std::map<std::string, std::vector<double>> rates, flushes;
  for (int r = 0; r < b.runs; ++r) {
    for (const auto& [name, d] : modes) {
      std::unique_ptr<Store> store;
      if (d) {
        auto s = open_store(fresh_dir(base, "write-" + name), *d);
        if (!s.ok()) {
          log->error("{}", s.error().to_string());
          return 2;
        }
        store = std::move(*s);
      }
      auto w = write_run(b, store.get(), 1 + r);
      if (!w.ok()) {
        log->error("{}", w.error().to_string());
        return 2;
      }
      rates[name].push_back(w->ops_per_s);
      flushes[name].push_back(w->flush_ms);
    }
  }
  const double memory = median(rates["memory"]);
  for (const auto& [name, d] : modes) {
    nlohmann::json j{{"bench", "store"},
                     {"part", "write"},
                     {"durability", name},
                     {"updates", b.updates},
                     {"batch", b.batch},
                     {"runs", b.runs},
                     {"local_ops_per_s_median", static_cast<long>(median(rates[name]))},
                     {"vs_memory", round_to(median(rates[name]) / memory, 3)},
                     {"final_flush_ms_median", round_to(median(flushes[name]), 2)}};
    std::cout << j.dump() << std::endl;
  }

  // Reload of a large replica: from its log, then from a snapshot (after compaction).
  const fs::path dir = fresh_dir(base, "reload");
  std::size_t log_bytes = 0;
  {
    auto s = open_store(dir, Durability::kNone);
    if (!s.ok()) {
      log->error("{}", s.error().to_string());
      return 2;
    }
    if (Status st = build_replica(b.reload_nodes, **s); !st.ok()) {
      log->error("{}", st.error().to_string());
      return 2;
    }
    log_bytes = (*s)->stats().bytes_appended;
  }
  for (const char* form : {"log", "snapshot"}) {
    if (std::string(form) == "snapshot") {
      auto s = open_store(dir, Durability::kNone);
      if (!s.ok() ||
          !(*s)->load(*std::make_unique<graph::Graph>(graph::ReplicaId{fnv1a64("bench"), 1}))
               .ok() ||
          !(*s)->compact().ok()) {
        log->error("could not compact the reload store");
        return 2;
      }
    }
    std::vector<double> ms;
    std::size_t nodes = 0;
    for (int r = 0; r < b.runs; ++r) {
      auto t = reload_ms(dir, nodes);
      if (!t.ok()) {
        log->error("{}", t.error().to_string());
        return 2;
      }
      ms.push_back(*t);
    }
    std::error_code ec;
    nlohmann::json j{{"bench", "store"},       {"part", "reload"},
                     {"from", form},           {"nodes", nodes},
                     {"log_bytes", log_bytes}, {"file_bytes", fs::file_size(dir / "data.mdb", ec)},
                     {"runs", b.runs},         {"reload_ms_median", round_to(median(ms), 1)}};
    std::cout << j.dump() << std::endl;
    if (nodes != static_cast<std::size_t>(b.reload_nodes)) {
      log->error("reloaded {} nodes, not {}", nodes, b.reload_nodes);
      return 1;
    }
  }
  return 0;
}

}  // namespace quiver::tools::bench
