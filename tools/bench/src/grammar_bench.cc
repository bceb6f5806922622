// The grammar benchmark (`quiver bench grammar`): synthetic grammars in both dialects and the
// cost of checking transactions against them.
#include "quiver/tools/bench/grammar_bench.h"

#include <chrono>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "quiver/agents/rules/grammar/grammar.h"
#include "quiver/agents/runtime/process/logging.h"
#include "quiver/base/rng.h"
#include "quiver/graph/graph.h"
#include "quiver/base/percentiles.h"

namespace quiver::tools::bench {
namespace {

using graph::NodeId;
using graph::Symbol;
using json = nlohmann::json;

// A synthetic 50-rule grammar: rule k rewrites a chain-with-branches pattern of 2..6 nodes, the
// edge labels distinct per rule (l<k>_<i>), one edge relabelled by the rule.
std::string synthetic_grammar(int rules) {
  std::string s =
      "grammar bench\ntypes { t0 t1 t2 t3 t4 t5 t6 t7 t8 t9 }\nallow attributes\nallow rt-poses\n";
  for (int k = 0; k < rules; ++k) {
    int n = 2 + k % 5;  // 2..6 nodes
    std::string nodes, lhs_edges, rhs_edges;
    for (int i = 0; i < n; ++i)
      nodes += " v" + std::to_string(i) + ":t" + std::to_string((k + i) % 10);
    for (int i = 1; i < n; ++i) {
      std::string e = " v" + std::to_string(i - 1) + "->v" + std::to_string(i) + "(l" +
                      std::to_string(k) + "_" + std::to_string(i) + ")";
      lhs_edges += e;
      if (i != 1) rhs_edges += e;
    }
    rhs_edges += " v0->v1(m" + std::to_string(k) + ")";
    s += "rule r" + std::to_string(k) + " : active {\n  {" + nodes + lhs_edges + " }\n  =>\n  {" +
         nodes + rhs_edges + " }\n}\n";
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
      nodes += "\t\tv" + std::to_string(i) + ":t" + std::to_string((k + i) % 10) + "(" +
               std::to_string(i * 100) + ",0)\n";
    for (int i = 1; i < n; ++i) {
      std::string e = "\t\tv" + std::to_string(i - 1) + "->v" + std::to_string(i) + "(l" +
                      std::to_string(k) + "_" + std::to_string(i) + ")\n";
      lhs_edges += e;
      if (i != 1) rhs_edges += e;
    }
    rhs_edges += "\t\tv0->v1(m" + std::to_string(k) + ")\n";
    s += "r" + std::to_string(k) + " : active(1)\n{\n\t{\n" + nodes + lhs_edges +
         "\t}\n\t=>\n\t{\n" + nodes + rhs_edges + "\t}\n\teffect\n\t{\n\t\t(forall x:t" +
         std::to_string(k % 10) +
         " (when (carries v0 x) (and (not (at x v1)) (at x v0))))\n\t}\n}\n";
  }
  return s;
}

}  // namespace

int run_grammar_bench(const GrammarBench& b) {
  const int nodes = b.nodes, rules = b.rules, checks = b.checks;
  const bool agm = b.agm;
  auto parsed =
      agents::parse_grammar(agm ? synthetic_grammar_agm(rules) : synthetic_grammar(rules), "bench");
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
          in.v.push_back(
              *tx.create_node("t" + std::to_string((k + i) % 10), "n" + std::to_string(made++)));
        for (int i = 1; i < n; ++i)
          (void)tx.insert_edge(in.v[i - 1], in.v[i],
                               Symbol("l" + std::to_string(k) + "_" + std::to_string(i)));
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

}  // namespace quiver::tools::bench
