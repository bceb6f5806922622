// Plans kept in the graph: the planner agent writes a mission's plan onto the plan node, follows the world along
// it and plans again when the world deviates; the step executor applies the steps it asks for.
#include "quiver/agents/apps/planning/planner_agent.h"

#include <nlohmann/json.hpp>

#include "quiver/agents/rules/planner/plan_replay.h"

namespace quiver::agents::inline apps::planning {

using namespace quiver::agents::planner;  // the search this agent runs

namespace {

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (start < text.size()) {
    auto end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    if (end > start) out.push_back(text.substr(start, end - start));
    start = end + 1;
  }
  return out;
}

std::string string_attr(const graph::Graph& g, graph::NodeId n, const char* name) {
  if (const graph::Value* v = g.attr(n, name))
    if (const auto* s = v->get_if<std::string>()) return *s;
  return {};
}

std::int64_t int_attr(const graph::Graph& g, graph::NodeId n, const char* name, std::int64_t fallback) {
  if (const graph::Value* v = g.attr(n, name))
    if (const auto* i = v->get_if<std::int64_t>()) return *i;
  return fallback;
}

}  // namespace

std::optional<graph::NodeId> find_plan_node(const graph::Graph& g, const std::string& name) {
  return g.find_node(name);
}

struct PlannerAgent::Impl {
  Grammar grammar;
  std::string mission_text;  // the text `mission` was parsed from
  std::optional<Mission> mission;
  Digest128 seen{};
  bool seen_any = false;
};

PlannerAgent::PlannerAgent(PlannerAgentOptions o, std::string name)
    : Agent(std::move(name)), impl_(std::make_unique<Impl>()), opt_(std::move(o)) {}
PlannerAgent::~PlannerAgent() = default;

void PlannerAgent::setup(AgentContext& ctx) {
  auto g = parse_grammar(opt_.domain_text, opt_.domain_source);
  if (!g.ok()) {
    state_ = "failed: " + g.error().message;
    ctx.log("PlannerAgent: " + state_);
    return;
  }
  impl_->grammar = std::move(*g);
  ctx.every(opt_.period_ns, [this, &ctx] {
    const Digest128 d = ctx.graph().digest();
    if (impl_->seen_any && d == impl_->seen) return;
    think(ctx);
    // What this agent wrote changes the digest too: remember the state after it.
    impl_->seen = ctx.graph().digest();
    impl_->seen_any = true;
  });
  if (opt_.on_setup) opt_.on_setup(*this, ctx);
}

void PlannerAgent::status(nlohmann::json& out) const {
  out["planner"] = state_;
  out["plans"] = plans_;
  out["replans"] = replans_;
  if (opt_.on_status) opt_.on_status(out);
}

void PlannerAgent::think(AgentContext& ctx) {
  graph::Graph& g = ctx.graph();
  std::optional<graph::NodeId> node = find_plan_node(g, opt_.plan_node);
  auto write = [&](const std::function<void(graph::Transaction&, graph::NodeId)>& fill) {
    auto tx = g.begin();
    graph::NodeId n;
    if (node) {
      n = *node;
    } else {
      auto created = tx.create_node("plan", opt_.plan_node);
      if (!created.ok()) return;
      n = *created;
    }
    fill(tx, n);
    auto r = tx.commit();
    if (!r.ok()) ctx.log("PlannerAgent: cannot write the plan: " + r.error().message);
  };
  // The mission: given, or the plan node's.
  const std::string text = !opt_.mission_text.empty() ? opt_.mission_text
                           : node                     ? string_attr(g, *node, "mission")
                                                      : std::string();
  if (text.empty()) return;  // nothing to do yet
  if (!impl_->mission || text != impl_->mission_text) {
    auto m = parse_mission(text, opt_.mission_source);
    impl_->mission_text = text;
    if (!m.ok()) {
      impl_->mission.reset();
      state_ = "failed: " + m.error().message;
      write([&](graph::Transaction& tx, graph::NodeId n) { (void)tx.set(n, "status", state_); });
      return;
    }
    impl_->mission = std::move(*m);
  }
  symbolic::World world =
      opt_.hide ? symbolic::read_world(g, impl_->grammar.types, [&](graph::NodeId n) { return opt_.hide(g, n); })
                : symbolic::read_world(g, impl_->grammar.types);
  Domain domain(impl_->grammar, world.vocabulary);
  auto cm = compile_mission(*impl_->mission, world);
  if (!cm.ok()) {
    state_ = "failed: " + cm.error().message;
    write([&](graph::Transaction& tx, graph::NodeId n) { (void)tx.set(n, "status", state_); });
    return;
  }
  const std::string old_status = node ? string_attr(g, *node, "status") : std::string();
  if (mission_holds(world.state, world.vocabulary, *cm)) {
    state_ = "achieved";
    if (old_status != "achieved")
      write([&](graph::Transaction& tx, graph::NodeId n) {
        (void)tx.set(n, "status", std::string("achieved"));
        (void)tx.set(n, "next", static_cast<std::int64_t>(lines_of(node ? string_attr(g, *node, "steps") : "").size()));
      });
    return;
  }
  // How far along the current plan is the world? The first step from which the rest still
  // applies and reaches the mission.
  const std::vector<std::string> steps = node ? lines_of(string_attr(g, *node, "steps")) : std::vector<std::string>{};
  const std::int64_t next = node ? int_attr(g, *node, "next", 0) : 0;
  const bool had_plan = !steps.empty() && old_status == "executing";
  if (had_plan) {
    for (std::size_t k = static_cast<std::size_t>(std::max<std::int64_t>(0, next)); k < steps.size(); ++k) {
      symbolic::State s = world.state;
      bool ok = true;
      for (std::size_t j = k; j < steps.size() && ok; ++j) {
        auto step = parse_step(steps[j], domain, world);
        if (!step.ok()) {
          ok = false;
          break;
        }
        auto after = domain.apply(s, *step);
        if (!after) ok = false;
        else s = std::move(*after);
      }
      if (ok && mission_holds(s, world.vocabulary, *cm)) {
        if (static_cast<std::int64_t>(k) != next)
          write([&](graph::Transaction& tx, graph::NodeId n) { (void)tx.set(n, "next", static_cast<std::int64_t>(k)); });
        state_ = "executing step " + std::to_string(k + 1) + " of " + std::to_string(steps.size());
        return;
      }
    }
    ++replans_;
    ctx.log("PlannerAgent: the world deviated from the plan; planning again");
  }
  PlanResult r = plan(domain, world.state, *cm, opt_.planner);
  ++plans_;
  const std::int64_t version = node ? int_attr(g, *node, "version", 0) + 1 : 1;
  if (!r.found()) {
    state_ = "failed: " + r.why;
    write([&](graph::Transaction& tx, graph::NodeId n) {
      (void)tx.set(n, "status", state_);
      (void)tx.set(n, "steps", std::string());
      (void)tx.set(n, "version", version);
    });
    return;
  }
  std::string text_steps;
  for (const Step& s : r.steps) text_steps += to_string(s, world) + "\n";
  state_ = "executing step 1 of " + std::to_string(r.steps.size());
  const std::int64_t replans = node ? int_attr(g, *node, "replans", 0) + (had_plan ? 1 : 0) : 0;
  write([&](graph::Transaction& tx, graph::NodeId n) {
    (void)tx.set(n, "steps", text_steps);
    (void)tx.set(n, "next", std::int64_t{0});
    (void)tx.set(n, "status", std::string("executing"));
    (void)tx.set(n, "version", version);
    (void)tx.set(n, "replans", replans);
    (void)tx.set(n, "cost", r.cost);
    (void)tx.set(n, "expansions", static_cast<std::int64_t>(r.expansions));
  });
  ctx.log("PlannerAgent: plan " + std::to_string(version) + ", " + std::to_string(r.steps.size()) + " steps, cost " +
          std::to_string(r.cost));
}

StepExecutor::StepExecutor(StepExecutorOptions o, std::string name) : Agent(std::move(name)), opt_(std::move(o)) {
  set_grammar_text(opt_.domain_text, opt_.domain_source);
}
StepExecutor::~StepExecutor() = default;

void StepExecutor::setup(AgentContext& ctx) {
  auto g = parse_grammar(opt_.domain_text, opt_.domain_source);
  if (!g.ok()) {
    ctx.log("StepExecutor: " + g.error().message);
    return;
  }
  grammar_ = std::make_unique<Grammar>(std::move(*g));
  ctx.every(20'000'000, [this, &ctx] {
    if (busy_) return;
    const graph::Graph& gr = ctx.graph();
    auto node = find_plan_node(gr, opt_.plan_node);
    if (!node || string_attr(gr, *node, "status") != "executing") return;
    const std::int64_t version = int_attr(gr, *node, "version", 0), next = int_attr(gr, *node, "next", 0);
    if (version == done_version_ && next == done_next_) return;
    busy_ = true;
    ctx.after(opt_.step_ns, [this, &ctx, version, next] {
      busy_ = false;
      execute(ctx, version, next);
    });
  });
}

void StepExecutor::execute(AgentContext& ctx, std::int64_t version, std::int64_t next) {
  graph::Graph& g = ctx.graph();
  auto node = find_plan_node(g, opt_.plan_node);
  if (!node || int_attr(g, *node, "version", 0) != version || int_attr(g, *node, "next", 0) != next) return;
  const std::vector<std::string> steps = lines_of(string_attr(g, *node, "steps"));
  if (next < 0 || static_cast<std::size_t>(next) >= steps.size()) return;
  symbolic::World world = symbolic::read_world(g, grammar_->types);
  Domain domain(*grammar_, world.vocabulary);
  auto step = parse_step(steps[next], domain, world);
  if (!step.ok()) {
    ctx.log("StepExecutor: " + step.error().message);
    return;
  }
  auto after = domain.apply(world.state, *step);
  if (!after) {
    ctx.log("StepExecutor: step " + std::to_string(next + 1) + " (" + steps[next] + ") does not apply here; waiting");
    return;
  }
  auto tx = g.begin();
  if (Status s = write_change(tx, world, world.state, *after); !s.ok()) {
    tx.abort();
    ctx.log("StepExecutor: " + s.error().message);
    return;
  }
  auto r = tx.commit();
  if (!r.ok()) {
    ctx.log("StepExecutor: the guard refuses step " + steps[next] + ": " + r.error().message);
    return;
  }
  done_version_ = version;
  done_next_ = next;
  ++executed_;
  if (versions_.empty() || versions_.back() != version) versions_.push_back(version);
  ctx.log("StepExecutor: did " + steps[next]);
}

}  // namespace quiver::agents::inline apps::planning
