// Your own agents in Quiver's simulator: two agent classes (a pinger that writes a "ping" node
// every 100 ms for 7 s, and a ponger that answers each one under a priority lock), registered
// with the simulator as roles, and two checks of your own, run from a scenario file with
// partitions, packet loss and kill -9 (pingpong.json). Virtual time: 12 s of it take a fraction
// of a second; a seed replays a run exactly. Built against the installed package (component sim).
//   sim_scenario examples/sim_scenario/pingpong.json [first-seed] [runs]
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>

#include "quiver/agents/runtime/api/agent.h"
#include "quiver/sim/scenario.h"
#include "quiver/sim/scenario_run.h"
using namespace quiver;
using agents::AgentContext;

class Pinger final : public agents::Agent {
 public:
  Pinger() : Agent("pinger") {}
  void setup(AgentContext& ctx) override {
    ctx.every(100'000'000, [this, &ctx] {
      if (ctx.now() > 7'000'000'000 || sent_ >= 70) return;  // then the team goes quiet
      auto tx = ctx.graph().begin();
      (void)tx.create_node("ping", "ping" + std::to_string(sent_++), {{graph::Symbol("answered"), graph::Value(false)}});
      (void)tx.commit();
    });
  }

 private:
  int sent_ = 0;
};

// One turn of the DSR loop per unanswered ping: lock it, answer it.
class Answer final : public agents::Action {
 public:
  Answer() : Action("answer") {}
  std::vector<agents::Match> find(AgentContext& ctx) override {
    std::vector<agents::Match> out;
    for (graph::NodeId n : ctx.graph().nodes_of_type("ping"))
      if (!ctx.graph().get<bool>(n, "answered").value_or(true))
        out.push_back(agents::Match{ctx.graph().name_of(n), {{"ping", n}}});
    return out;
  }
  bool holds(AgentContext& ctx, const agents::Match& m) override { return ctx.graph().has_node(m.at("ping")); }
  std::optional<agents::LockNeed> lock(AgentContext&, const agents::Match& m) override {
    return agents::LockNeed{m.at("ping"), 1};
  }
  Status start(AgentContext&, const agents::Match&) override { return {}; }
  Status finish(AgentContext& ctx, const agents::Match& m) override {
    auto tx = ctx.graph().begin();
    if (auto s = tx.set(m.at("ping"), "answered", graph::Value(true)); !s.ok()) return s;
    if (auto s = tx.set(m.at("ping"), "by", graph::Value(ctx.name())); !s.ok()) return s;
    return tx.commit().ok() ? Status{} : make_error(ErrorCode::kRefused, "the answer was refused");
  }
  void cancel(AgentContext&, const agents::Match&, agents::CancelReason) override {}
};

class Ponger final : public agents::Agent {
 public:
  explicit Ponger(std::string name) : Agent(std::move(name)) {}
  void setup(AgentContext&) override { add_action(std::make_unique<Answer>()); }
};

// Checks: every ping answered (on a replica that saw them all), and every replica equal.
struct EveryPingAnswered final : sim::Check {
  int min_pings = 1;
  void finish(sim::ScenarioRun& run, std::vector<std::string>& failures) override {
    const graph::Graph* g = run.host().graph(run.host().index("pinger"));
    if (g == nullptr) return failures.push_back("the pinger is down at the end");
    int pings = 0, open = 0;
    for (graph::NodeId n : g->nodes_of_type("ping")) {
      ++pings;
      if (!g->get<bool>(n, "answered").value_or(false)) ++open;
    }
    if (pings < min_pings) failures.push_back(std::to_string(pings) + " pings, fewer than " + std::to_string(min_pings));
    if (open > 0) failures.push_back(std::to_string(open) + " of " + std::to_string(pings) + " pings unanswered");
  }
};

struct ReplicasEqual final : sim::Check {
  void finish(sim::ScenarioRun& run, std::vector<std::string>& failures) override {
    sim::AgentHost& h = run.host();
    for (int i = 1; i < h.size(); ++i)
      if (!h.graph(i) || !h.graph(0) || h.graph(i)->digest() != h.graph(0)->digest())
        failures.push_back(h.name(i) + " differs from " + h.name(0));
  }
};

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s SCENARIO.json [first-seed] [runs]\n", argv[0]);
    return 2;
  }
  sim::ScenarioApp app("pingpong");
  app.role("pinger", [](sim::ScenarioRun&) { return std::make_unique<Pinger>(); });
  // A role may run under several names: each agent is made with the name the scenario gives it.
  app.role("ponger", [](sim::ScenarioRun& run) { return std::make_unique<Ponger>(run.agent_name()); });
  app.check("every_ping_answered", [](const nlohmann::json& p, const std::string& where) -> Result<std::unique_ptr<sim::Check>> {
    auto c = std::make_unique<EveryPingAnswered>();
    if (!p.is_object() || !p.value("min_pings", nlohmann::json(1)).is_number_integer())
      return make_error(ErrorCode::kInvalidArgument, where + ": expected {\"min_pings\": N}");
    c->min_pings = p.value("min_pings", 1);
    return std::unique_ptr<sim::Check>(std::move(c));
  });
  app.check("replicas_equal", [](const nlohmann::json& p, const std::string& where) -> Result<std::unique_ptr<sim::Check>> {
    if (!p.is_boolean()) return make_error(ErrorCode::kInvalidArgument, where + ": expected true or false");
    return p.get<bool>() ? std::unique_ptr<sim::Check>(std::make_unique<ReplicasEqual>()) : nullptr;
  });
  auto scenario = sim::Scenario::load(argv[1], app);
  if (!scenario.ok()) {
    std::fprintf(stderr, "%s\n", scenario.error().to_string().c_str());
    return 2;
  }
  const std::uint64_t first = argc > 2 ? std::strtoull(argv[2], nullptr, 10) : 1;
  const int runs = argc > 3 ? std::atoi(argv[3]) : 5;
  int failed = 0;
  for (int k = 0; k < runs; ++k) {
    sim::ScenarioOutcome out = sim::run_scenario(*scenario, app, first + static_cast<std::uint64_t>(k));
    std::printf("%s\n", out.to_json().dump().c_str());
    failed += out.passed ? 0 : 1;
  }
  return failed == 0 ? 0 : 1;
}
