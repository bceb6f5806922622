// quiver bench grammar / locks.

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <future>
#include <iostream>
#include <nlohmann/json.hpp>
#include <thread>

#include "bench_stats.h"
#include "commands.h"
#include "quiver/agents/runtime/process/logging.h"
#include "quiver/agents/runtime/process/dds_replica.h"
#include "quiver/agents/rules/grammar/grammar.h"
#include "quiver/agents/rules/locks/locks.h"
#include "quiver/base/rng.h"
#include "quiver/sim/simulator.h"

namespace quiver::tools {
namespace {

using graph::NodeId;
using graph::Symbol;
using json = nlohmann::json;

// ------------------------------------------------------------------ grammar

// A synthetic 50-rule grammar: rule k rewrites a chain-with-branches pattern of 2..6 nodes, the
// edge labels distinct per rule (l<k>_<i>), one edge relabelled by the rule.
std::string synthetic_grammar(int rules) {
  std::string s = "grammar bench\ntypes { t0 t1 t2 t3 t4 t5 t6 t7 t8 t9 }\nallow attributes\nallow rt-poses\n";
  for (int k = 0; k < rules; ++k) {
    int n = 2 + k % 5;  // 2..6 nodes
    std::string nodes, lhs_edges, rhs_edges;
    for (int i = 0; i < n; ++i) nodes += " v" + std::to_string(i) + ":t" + std::to_string((k + i) % 10);
    for (int i = 1; i < n; ++i) {
      std::string e = " v" + std::to_string(i - 1) + "->v" + std::to_string(i) + "(l" + std::to_string(k) + "_" + std::to_string(i) + ")";
      lhs_edges += e;
      if (i != 1) rhs_edges += e;
    }
    rhs_edges += " v0->v1(m" + std::to_string(k) + ")";
    s += "rule r" + std::to_string(k) + " : active {\n  {" + nodes + lhs_edges + " }\n  =>\n  {" + nodes + rhs_edges + " }\n}\n";
  }
  return s;
}

// The same rules in AGM's dialect, each with an effect: what v0 carries moves with the rewrite
// (nothing is carried in the bench's world, so the effect looks and changes nothing).
std::string synthetic_grammar_agm(int rules) {
  std::string s = "name=bench\n===\ntypes\n{\n";
  for (int t = 0; t < 10; ++t) s += "\t(t" + std::to_string(t) + ")\n";
  s += "}\n===\n";
  for (int k = 0; k < rules; ++k) {
    int n = 2 + k % 5;
    std::string nodes, lhs_edges, rhs_edges;
    for (int i = 0; i < n; ++i)
      nodes += "\t\tv" + std::to_string(i) + ":t" + std::to_string((k + i) % 10) + "(" + std::to_string(i * 100) + ",0)\n";
    for (int i = 1; i < n; ++i) {
      std::string e = "\t\tv" + std::to_string(i - 1) + "->v" + std::to_string(i) + "(l" + std::to_string(k) + "_" +
                      std::to_string(i) + ")\n";
      lhs_edges += e;
      if (i != 1) rhs_edges += e;
    }
    rhs_edges += "\t\tv0->v1(m" + std::to_string(k) + ")\n";
    s += "r" + std::to_string(k) + " : active(1)\n{\n\t{\n" + nodes + lhs_edges + "\t}\n\t=>\n\t{\n" + nodes + rhs_edges +
         "\t}\n\teffect\n\t{\n\t\t(forall x:t" + std::to_string(k % 10) +
         " (when (carries v0 x) (and (not (at x v1)) (at x v0))))\n\t}\n}\n";
  }
  return s;
}

int run_bench_grammar(int nodes, int rules, int checks, bool agm) {
  auto parsed = agents::parse_grammar(agm ? synthetic_grammar_agm(rules) : synthetic_grammar(rules), "bench");
  if (!parsed.ok()) {
    agents::named_logger("quiver bench grammar")->error("{}", parsed.error().to_string());
    return 2;
  }
  agents::GrammarChecker checker(std::move(*parsed));
  graph::Graph g(graph::ReplicaId{1, 1});
  // Instances of every rule's left-hand side, until the graph has `nodes` nodes; plus noise
  // edges so that degrees are not trivially 1.
  struct Instance {
    int rule;
    std::vector<NodeId> v;
  };
  std::vector<Instance> inst;
  Rng rng(3);
  {
    auto tx = g.begin();
    int made = 0;
    for (int round = 0; made < nodes; ++round)
      for (int k = 0; k < rules && made < nodes; ++k) {
        int n = 2 + k % 5;
        Instance in{k, {}};
        for (int i = 0; i < n; ++i)
          in.v.push_back(*tx.create_node("t" + std::to_string((k + i) % 10), "n" + std::to_string(made++)));
        for (int i = 1; i < n; ++i)
          (void)tx.insert_edge(in.v[i - 1], in.v[i], Symbol("l" + std::to_string(k) + "_" + std::to_string(i)));
        inst.push_back(std::move(in));
      }
    (void)tx.commit();
  }
  {
    auto all = g.nodes();
    auto tx = g.begin();
    for (std::size_t i = 0; i < all.size(); ++i)
      (void)tx.insert_edge(all[i], all[rng.below(all.size())], Symbol("near"));
    (void)tx.commit();
  }
  std::vector<double> structural_us, attr_us;
  int accepted = 0;
  using Clock = std::chrono::steady_clock;
  for (int c = 0; c < checks; ++c) {
    const Instance& in = inst[rng.below(inst.size())];
    auto tx = g.begin();
    (void)tx.delete_edge(in.v[0], in.v[1], Symbol("l" + std::to_string(in.rule) + "_1"));
    (void)tx.insert_edge(in.v[0], in.v[1], Symbol("m" + std::to_string(in.rule)));
    auto t0 = Clock::now();
    Status s = checker.check(g, tx.ops());
    structural_us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
    accepted += s.ok() ? 1 : 0;
    auto ta = g.begin();
    (void)ta.set(in.v[0], Symbol("x"), graph::Value(1.0));
    auto t1 = Clock::now();
    Status sa = checker.check(g, ta.ops());
    attr_us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t1).count());
    accepted += sa.ok() ? 0 : -1000000;
  }
  json out;
  out["bench"] = "grammar";
  out["dialect"] = agm ? "agm" : "quiver";
  out["rules"] = rules;
  out["nodes"] = g.node_count();
  out["checks"] = checks;
  out["accepted"] = accepted;
  const Percentiles structural(structural_us);
  out["check_us_p50"] = round_to(structural.at(0.5), 2);
  out["check_us_p99"] = round_to(structural.at(0.99), 2);
  out["attribute_txn_check_us_p50"] = round_to(Percentiles(attr_us).at(0.5), 3);
  std::cout << out.dump() << std::endl;
  return accepted == checks ? 0 : 1;
}

// ------------------------------------------------------------------ locks

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
    r->locks = std::make_unique<agents::LockManager>(r->a->graph(), &r->a->replicator(), agents::monotonic_ns);
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
      ready = ready && call(*r, [&] { return r->a->graph().has_node(scope) && r->a->replicator().live_peer_count() == rs.size() - 1; });
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
      while (call(*r, [&] { return r->locks->winner(scope).has_value(); })) std::this_thread::yield();
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

void add_agents_bench_commands(CLI::App& app) {
  CLI::App* bench = app.get_subcommand("bench");
  auto g = bench->add_subcommand("grammar", "Grammar check cost per transaction (50 rules, 10k nodes)");
  auto nodes = std::make_shared<int>(10000), rules = std::make_shared<int>(50), checks = std::make_shared<int>(20000);
  g->add_option("--nodes", *nodes)->check(CLI::Range(1, 10'000'000))->capture_default_str();
  g->add_option("--rules", *rules)->check(CLI::Range(1, 100'000))->capture_default_str();
  g->add_option("--checks", *checks)->check(CLI::Range(1, 100'000'000))->capture_default_str();
  auto agm = std::make_shared<bool>(false);
  g->add_flag("--agm", *agm,
              "the same rules in AGM's dialect, each with an effect (a forall over what v0 carries, anchored on v0)");
  g->callback([=] { set_exit_code(run_bench_grammar(*nodes, *rules, *checks, *agm)); });

  auto l = bench->add_subcommand("locks", "Lock acquire latency: in the simulator and over DDS (loopback)");
  auto agents = std::make_shared<int>(3), rounds = std::make_shared<int>(300);
  auto domain = std::make_shared<std::uint32_t>(78);
  l->add_option("--agents", *agents)->check(CLI::Range(2, 16))->capture_default_str();
  l->add_option("--rounds", *rounds)->check(CLI::Range(1, 1'000'000))->capture_default_str();
  l->add_option("--domain", *domain)->check(CLI::Range(0, 230))->capture_default_str();
  l->callback([=] {
    std::cout << lock_latency_in_simulator(8, 1).dump() << std::endl;
    json d = lock_latency_over_dds(*agents, *rounds, *domain);
    std::cout << d.dump() << std::endl;
    set_exit_code(d.is_null() ? 1 : 0);
  });
}

}  // namespace quiver::tools
