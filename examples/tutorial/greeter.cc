// The tutorial's agent (docs/agents.md, "A complete agent"): it greets every person in the
// shared graph, one action run per person under a priority lock on that person; it counts the
// person changes it sees, reports every five seconds whether it hears an agent named `speech`,
// and has an option of its own (--text). The second agent of the tutorial is `quiver agent --name
// speech`. CI builds it against the installed package and runs the pair
// (tests/packaging/examples_against_installed.sh). Keep it the same as the block in docs/agents.md.
#include <CLI/CLI.hpp>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "quiver/agents/runtime/api/agent.h"
#include "quiver/agents/runtime/process/process_host.h"
using namespace quiver;
using agents::AgentContext;

class Greet final : public agents::Action {
 public:
  explicit Greet(std::string text) : Action("greet"), text_(std::move(text)) {}
  std::vector<agents::Match> find(AgentContext& ctx) override {
    std::vector<agents::Match> out;
    for (graph::NodeId n : ctx.graph().nodes_of_type("person"))
      if (!ctx.graph().get<bool>(n, "greeted").value_or(false))
        out.push_back(agents::Match{ctx.graph().name_of(n), {{"person", n}}});
    return out;
  }
  bool holds(AgentContext& ctx, const agents::Match& m) override { return ctx.graph().has_node(m.at("person")); }
  std::optional<agents::LockNeed> lock(AgentContext&, const agents::Match& m) override {
    return agents::LockNeed{m.at("person"), 1};
  }
  Status start(AgentContext& ctx, const agents::Match& m) override {  // the mark others see
    auto tx = ctx.graph().begin();
    if (auto s = tx.set(m.at("person"), "greeting", graph::Value("executing")); !s.ok()) return s;
    auto c = tx.commit();
    return c.ok() ? Status{} : Status(c.error());
  }
  Status finish(AgentContext& ctx, const agents::Match& m) override {  // the result
    auto tx = ctx.graph().begin();
    if (auto s = tx.set(m.at("person"), "greeting", graph::Value(text_)); !s.ok()) return s;
    if (auto s = tx.set(m.at("person"), "greeted", graph::Value(true)); !s.ok()) return s;
    auto c = tx.commit();
    return c.ok() ? Status{} : Status(c.error());
  }
  void cancel(AgentContext& ctx, const agents::Match& m, agents::CancelReason why) override {
    ctx.log("greeting " + m.key + " cancelled: " + agents::to_string(why));
    if (!ctx.graph().has_node(m.at("person"))) return;
    auto tx = ctx.graph().begin();
    (void)tx.remove_attr(m.at("person"), "greeting");  // take the mark back
    (void)tx.commit();
  }

 private:
  std::string text_;
};

class Greeter final : public agents::Agent {
 public:
  Greeter(std::string name, std::string text) : Agent(std::move(name)), text_(std::move(text)) {}
  void setup(AgentContext& ctx) override {
    add_action(std::make_unique<Greet>(text_), agents::ChangeFilter{{"person"}, {}, {}});
    subscribe(agents::ChangeFilter{{"person"}, {}, {}},
              [this](AgentContext&, const graph::ChangeBatch& b) { seen_ += b.nodes.size(); });
    ctx.every(5'000'000'000, [&ctx] { ctx.log(ctx.hears("speech") ? "speech is here" : "no speech"); });
  }
  void teardown(AgentContext& ctx) override { ctx.log("bye"); }
  void status(nlohmann::json& out) const override { out["person_changes"] = seen_; }

 private:
  std::string text_;
  std::size_t seen_ = 0;
};

int main(int argc, char** argv) {
  CLI::App app{"greeter: greets every person in the shared graph"};
  std::string text = "Hello";
  app.add_option("--text", text, "what to say")->capture_default_str();
  agents::ProcessFlags flags;
  flags.add_all(&app);  // --domain, --world, --status-ms, --run-for, ...
  CLI11_PARSE(app, argc, argv);
  Greeter agent("greeter", text);
  return agents::run_process(agent, flags);
}
