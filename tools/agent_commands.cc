// quiver agent: a replicating agent process. quiver dump: an observer that prints the graph.

#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "quiver/agents/runtime/process/logging.h"
#include "dds_options.h"
#include "observer.h"
#include "quiver/agents/runtime/process/dds_replica.h"
#include "quiver/agents/rules/locks/locks.h"
#include "quiver/graph/world_file.h"
#include "quiver/base/rng.h"
#include "quiver/sim/workload.h"

namespace quiver::tools {
namespace {

using agents::DdsReplica;

// The testing agent of `quiver agent`: random graph churn at a rate, for a while (or nothing: a
// replica that only follows), under a grammar if given. Its status lines say whether it still
// writes.
class ChurnAgent : public agents::Agent {
 public:
  ChurnAgent(std::string name, double hz, double for_s, double count_hz)
      : Agent(std::move(name)), hz_(hz), for_s_(for_s), count_hz_(count_hz) {}
  /// Testing: compete for the priority lock of node `node` (once the world holds it), hold it
  /// `hold_ms`, release it, and claim it again; each hold is printed as "held START END" (the
  /// host's monotonic clock, ns), so that a test can check that no two agents held it at once.
  void contend(std::string node, double hold_ms) {
    contend_ = std::move(node);
    hold_ns_ = static_cast<std::int64_t>(hold_ms * 1e6);
  }
  void setup(agents::AgentContext& ctx) override {
    start_ns_ = ctx.now();
    clock_ = [&ctx] { return ctx.now(); };
    if (count_hz_ > 0) start_counting(ctx);
    if (!contend_.empty()) ctx.every(5'000'000, [this, &ctx] { contend_step(ctx); });
    if (hz_ <= 0) return;
    ctx.every(static_cast<std::int64_t>(1e9 / hz_), [this, &ctx] {
      if (churning(ctx.now())) churn_.step(ctx.graph(), ctx.rng(), ctx.now());
    });
  }
  void status(nlohmann::json& out) const override {
    out["churning"] = clock_ && churning(clock_());
    if (!contend_.empty()) {
      out["holds"] = holds_;
      out["holds_lost"] = lost_;  // ended before their time: another agent's claim took over
    }
  }

 private:
  bool churning(std::int64_t now) const { return hz_ > 0 && (for_s_ <= 0 || now - start_ns_ < for_s_ * 1e9); }
  // Crash tests: node "<name>.counter" holds `count`, which goes up by one per commit; the line
  // "acked N" is printed once the commit that wrote N has returned. A replica reloaded from its
  // store starts from the count it holds.
  void start_counting(agents::AgentContext& ctx) {
    const std::string node = name() + ".counter";
    if (auto id = ctx.graph().find_node(node)) {
      counter_ = *id;
      if (auto n = ctx.graph().get<std::int64_t>(*id, "count"); n.ok()) count_ = *n;
    } else {
      auto tx = ctx.graph().begin();
      auto id2 = tx.create_node("counter", node, {{graph::Symbol("count"), graph::Value(std::int64_t{0})}});
      if (!id2.ok() || !tx.commit().ok()) return;
      counter_ = *id2;
    }
    std::cout << "loaded " << count_ << std::endl;
    ctx.every(static_cast<std::int64_t>(1e9 / count_hz_), [this, &ctx] {
      auto tx = ctx.graph().begin();
      if (!tx.set(counter_, "count", graph::Value(count_ + 1)).ok() || !tx.commit().ok()) return;
      ++count_;
      std::cout << "acked " << count_ << std::endl;
    });
  }
  void contend_step(agents::AgentContext& ctx) {
    auto node = ctx.graph().find_node(contend_);
    if (!node) return;
    agents::LockManager& locks = ctx.locks();
    const std::int64_t now = ctx.now();
    if (held_since_ >= 0) {
      // Released after its time, or lost (a higher claim, the holder cut off): the hold ends.
      const bool still = locks.holds(*node);
      if (still && now - held_since_ < hold_ns_) return;
      std::cout << "held " << held_since_ << " " << now << std::endl;
      ++holds_;
      if (!still) ++lost_;
      held_since_ = -1;
      (void)locks.release(*node);
      next_claim_ns_ = now + hold_ns_ / 2;  // give the others a turn
      return;
    }
    if (locks.holds(*node)) {
      held_since_ = now;
      return;
    }
    if (!locks.pending(*node) && now >= next_claim_ns_ && !locks.locked_by_other(*node)) (void)locks.acquire(*node, 1);
  }
  double hz_, for_s_, count_hz_;
  std::string contend_;
  std::int64_t hold_ns_ = 0, held_since_ = -1, next_claim_ns_ = 0;
  int holds_ = 0, lost_ = 0;
  graph::NodeId counter_{};
  std::int64_t count_ = 0;
  std::int64_t start_ns_ = 0;
  std::function<std::int64_t()> clock_;
  sim::Churn churn_{[] {
    sim::ChurnMix mix;
    mix.spare_type = "counter";  // the crash tests' counter is the count's alone
    return mix;
  }()};
};

struct AgentFlags {
  std::string name;
  std::string grammar;
  agents::ProcessFlags process;
  double churn_hz = 0;
  double churn_for_s = 0;
  double count_hz = 0;
  std::string contend;
  double hold_ms = 100;
};

int run_agent(const AgentFlags& f) {
  ChurnAgent agent(f.name, f.churn_hz, f.churn_for_s, f.count_hz);
  if (!f.grammar.empty()) agent.set_grammar_file(f.grammar);
  if (!f.contend.empty()) agent.contend(f.contend, f.hold_ms);
  return agents::run_process(agent, f.process);
}

struct DumpFlags {
  DdsFlags dds;
  bool json = false;
  bool digest = false;
  double timeout_s = 10;
};

void print_graph(const graph::Graph& g) {
  for (graph::NodeId id : g.nodes()) {
    std::cout << g.name_of(id) << " : " << g.type_of(id).str();
    if (auto p = g.rt_parent(id)) std::cout << "   (RT parent " << g.name_of(*p) << ")";
    std::cout << "\n";
    for (graph::Symbol a : g.attr_names(id)) {
      auto values = g.attr_values(id, a);
      std::cout << "    " << a.str() << " = " << values[0].value.to_string();
      if (values.size() > 1) std::cout << "   [" << values.size() << " concurrent values]";
      std::cout << "\n";
    }
    for (const graph::EdgeKey& k : g.edges_from(id))
      if (!(k.type == graph::symbols::rt())) std::cout << "    -[" << k.type.str() << "]-> " << g.name_of(k.to) << "\n";
  }
}

int run_dump(const DumpFlags& f) {
  auto joined = join_as_observer(f.dds, "quiver-dump", f.timeout_s);
  if (!joined.ok()) {
    const bool timeout = joined.error().code == ErrorCode::kTimeout;
    agents::named_logger("quiver dump")
        ->error("{}", timeout ? joined.error().message : joined.error().to_string());
    return timeout ? 1 : 2;
  }
  DdsReplica& a = **joined;
  if (f.digest) std::cout << a.graph().digest().hex() << std::endl;
  else if (f.json) std::cout << graph::save_world(a.graph());
  else print_graph(a.graph());
  return 0;
}

}  // namespace

void add_agent_commands(CLI::App& app) {
  auto af = std::make_shared<AgentFlags>();
  auto* agent = app.add_subcommand("agent", "Run a replicating agent (one replica, Cyclone DDS, no executive)");
  agent->add_option("--name", af->name, "agent name (its id derives from it)")->required();
  agent->add_option("--grammar", af->grammar, "check every local change against this grammar file (docs/grammar.md)");
  af->process.join_wait_s = 0;  // a test agent starts at once (before add_all: its default)
  af->process.add_all(agent);
  agent->add_option("--churn-hz", af->churn_hz, "testing: make random changes at this many transactions per second")
      ->check(CLI::Range(0.0, 100000.0));
  agent->add_option("--churn-for", af->churn_for_s, "testing: stop the random changes after this many seconds")
      ->check(CLI::Range(0.0, 1e7));
  agent->add_option("--count-hz", af->count_hz,
                    "testing: raise the attribute 'count' of node NAME.counter by one this many times a second, "
                    "printing 'acked N' once each commit has returned (crash tests)")
      ->check(CLI::Range(0.0, 100000.0));
  agent->add_option("--contend", af->contend,
                    "testing: compete for the lock of this node (once the world holds it), printing 'held START END' "
                    "(monotonic ns) for each hold; the status counts holds and holds_lost");
  agent->add_option("--hold-ms", af->hold_ms, "testing: how long each --contend hold lasts")
      ->check(CLI::Range(1.0, 60000.0))
      ->capture_default_str();
  agent->callback([af] { set_exit_code(run_agent(*af)); });

  auto df = std::make_shared<DumpFlags>();
  auto* dump = app.add_subcommand("dump", "Join as an observer, wait until synced, print the graph and leave");
  df->dds.add_to(dump);
  auto* fmt = dump->add_option_group("format");
  fmt->add_flag("--json", df->json, "print a JSON world file");
  fmt->add_flag("--digest", df->digest, "print the state digest only");
  fmt->require_option(0, 1);
  dump->add_option("--timeout", df->timeout_s, "give up after this many seconds")
      ->check(CLI::Range(0.1, 3600.0))
      ->capture_default_str();
  dump->callback([df] { set_exit_code(run_dump(*df)); });
}

}  // namespace quiver::tools
