// The lock benchmark (`quiver bench locks`): acquire latency in the simulator and over DDS.
#include "quiver/tools/bench/lock_bench.h"

#include <atomic>
#include <chrono>
#include <future>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <thread>
#include <vector>

#include "quiver/agents/rules/locks/locks.h"
#include "quiver/agents/runtime/process/dds_replica.h"
#include "quiver/agents/runtime/process/logging.h"
#include "quiver/sim/simulator.h"
#include "quiver/base/percentiles.h"

namespace quiver::tools::bench {
namespace {

using graph::NodeId;
using json = nlohmann::json;

json lock_latency_in_simulator(int agents, std::uint64_t seed) {
  sim::SimConfig c;
  c.seed = seed;
  c.agents = agents;
  c.steps = 2000;
  c.locks.enabled = true;
  sim::SimResult r = sim::run_simulation(c);
  std::vector<double> ms;
  for (auto ns : r.lock_acquire_latency_ns) ms.push_back(ns / 1e6);
  json j;
  j["bench"] = "locks";
  j["mode"] = "simulator";
  j["agents"] = agents;
  j["network_delay_ms"] = "0.1-2";
  j["acquisitions"] = ms.size();
  const Percentiles pct(ms);
  j["acquire_ms_p50"] = round_to(pct.at(0.5), 2);
  j["acquire_ms_p99"] = round_to(pct.at(0.99), 2);
  j["overlap_connected_ms"] = r.lock_overlap_connected_ns / 1e6;
  return j;
}

json lock_latency_over_dds(int agents, int rounds, std::uint32_t domain) {
  struct Runner {
    std::unique_ptr<agents::DdsReplica> a;
    std::unique_ptr<agents::LockManager> locks;
    std::thread t;
    std::atomic<bool> running{true};
  };
  std::vector<std::unique_ptr<Runner>> rs;
  for (int i = 0; i < agents; ++i) {
    agents::DdsReplicaOptions o;
    o.name = "lockbench" + std::to_string(i);
    o.dds.domain = domain;
    o.dds.own_domain_instance = true;
    auto a = agents::DdsReplica::create(o);
    if (!a.ok()) {
      agents::named_logger("quiver bench locks")->error("{}", a.error().to_string());
      return json();
    }
    auto r = std::make_unique<Runner>();
    r->a = std::move(*a);
    r->locks = std::make_unique<agents::LockManager>(r->a->graph(), &r->a->replicator(),
                                                     agents::monotonic_ns);
    r->locks->install();
    rs.push_back(std::move(r));
  }
  auto call = [](Runner& r, auto fn) {
    std::promise<decltype(fn())> p;
    auto f = p.get_future();
    r.a->post([&] { p.set_value(fn()); });
    return f.get();
  };
  for (auto& r : rs) {
    Runner* raw = r.get();
    r->t = std::thread([raw] {
      while (raw->running.load()) {
        raw->a->spin_once(2'000'000);
        raw->locks->tick();
      }
    });
  }
  Runner& me = *rs[0];
  NodeId scope = call(me, [&] {
    auto tx = me.a->graph().begin();
    auto id = *tx.create_node("scope", "scope");
    (void)tx.commit();
    return id;
  });
  // Everyone must know the scope and each other first.
  for (int i = 0; i < 500; ++i) {
    bool ready = true;
    for (auto& r : rs)
      ready = ready && call(*r, [&] {
                return r->a->graph().has_node(scope) &&
                       r->a->replicator().live_peer_count() == rs.size() - 1;
              });
    if (ready) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  std::vector<double> us;
  for (int k = 0; k < rounds; ++k) {
    const std::int64_t t0 = agents::monotonic_ns();
    if (!call(me, [&] { return me.locks->acquire(scope, 1).ok(); })) continue;
    while (!call(me, [&] { return me.locks->holds(scope); })) std::this_thread::yield();
    us.push_back((agents::monotonic_ns() - t0) / 1e3);
    call(me, [&] { return me.locks->release(scope).ok(); });
    // Wait until every agent saw the release.
    for (auto& r : rs)
      while (call(*r, [&] { return r->locks->winner(scope).has_value(); }))
        std::this_thread::yield();
  }
  for (auto& r : rs) {
    r->running.store(false);
    r->a->stop();
    r->t.join();
  }
  json j;
  j["bench"] = "locks";
  j["mode"] = "dds";
  j["agents"] = agents;
  j["acquisitions"] = us.size();
  const Percentiles pct(us);
  j["acquire_us_p50"] = round_to(pct.at(0.5), 1);
  j["acquire_us_p99"] = round_to(pct.at(0.99), 1);
  return j;
}

}  // namespace

int run_lock_bench(const LockBench& b) {
  std::cout << lock_latency_in_simulator(8, 1).dump() << std::endl;
  json d = lock_latency_over_dds(b.agents, b.rounds, b.domain);
  std::cout << d.dump() << std::endl;
  return d.is_null() ? 1 : 0;
}

}  // namespace quiver::tools::bench
