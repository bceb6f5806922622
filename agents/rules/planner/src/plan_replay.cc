// Plans on a real replica: a step written as one transaction, a plan replayed through the grammar checker, and
// plan steps read back from text.
#include "quiver/agents/rules/planner/plan_replay.h"

#include <algorithm>
#include <set>

#include "quiver/agents/rules/grammar/retype.h"

namespace quiver::agents::inline rules::planner {

using symbolic::Edge;
using symbolic::kNoNode;
using symbolic::NodeIx;
using symbolic::State;

namespace {

std::string unique_name(const graph::Graph& g, const std::set<std::string>& taken, std::string base) {
  std::string name = base;
  for (int k = 2; g.find_node(name) || taken.count(name); ++k) name = base + "_" + std::to_string(k);
  return name;
}

}  // namespace

Status write_change(graph::Transaction& tx, symbolic::World& world, const State& before, const State& after) {
  const symbolic::Vocabulary& voc = world.vocabulary;
  graph::Graph& g = tx.graph();
  const auto rt = voc.find_label("RT");
  // Retypes first: replace_node_type wants the node untouched.
  for (NodeIx n = 0; n < before.size() && n < after.size(); ++n) {
    if (!before.alive(n) || !after.alive(n) || before.type(n) == after.type(n)) continue;
    auto id = replace_node_type(tx, world.ids[n], voc.type_name(after.type(n)));
    if (!id.ok()) return id.error();
    world.ids[n] = *id;
  }
  std::set<std::string> taken;
  for (NodeIx n = 0; n < after.size(); ++n) {
    if (!after.alive(n) || (n < before.size() && before.alive(n))) continue;
    while (world.ids.size() <= n) {
      world.ids.emplace_back();
      world.names.emplace_back();
      world.agm_ids.emplace_back();
    }
    const std::string label = world.label(n);
    const std::string& type = voc.type_name(after.type(n));
    const bool agm = world.max_agm_id >= 0;
    // Named so that the plan's later steps find it again by its label (World::find).
    const std::string name = unique_name(g, taken, agm ? type + "_" + label : label);
    taken.insert(name);
    std::vector<std::pair<graph::Symbol, graph::Value>> attrs;
    if (agm) attrs.emplace_back(graph::Symbol("agm_id"), graph::Value(label));
    auto id = tx.create_node(type, name, std::move(attrs));
    if (!id.ok()) return id.error();
    world.ids[n] = *id;
    world.names[n] = name;
    world.agm_ids[n] = agm ? label : std::string();  // label() of created nodes stays as planned
  }
  for (NodeIx n = 0; n < before.size(); ++n)
    if (before.alive(n) && !after.alive(n)) {
      Status s = tx.delete_node(world.ids[n]);
      if (!s.ok()) return s;
    }
  auto is_rt = [&](const Edge& e) { return rt && e.label == *rt; };
  // RT children that get a new parent in this change (set_rt moves them).
  std::set<NodeIx> moved;
  for (const Edge& e : after.edges())
    if (is_rt(e) && !before.has_edge(e.from, e.to, e.label)) moved.insert(e.to);
  for (const Edge& e : before.edges()) {
    if (after.has_edge(e.from, e.to, e.label) || !after.alive(e.from) || !after.alive(e.to)) continue;
    Status s = is_rt(e) ? (moved.count(e.to) ? Status{} : tx.remove_rt(world.ids[e.to]))
                        : tx.delete_edge(world.ids[e.from], world.ids[e.to], voc.label_name(e.label));
    if (!s.ok()) return s;
  }
  for (const Edge& e : after.edges()) {
    if (e.from < before.size() && e.to < before.size() && before.has_edge(e.from, e.to, e.label)) continue;
    Status s = is_rt(e) ? tx.set_rt(world.ids[e.from], world.ids[e.to], graph::Pose::identity())
                        : tx.insert_edge(world.ids[e.from], world.ids[e.to], graph::Symbol(voc.label_name(e.label)));
    if (!s.ok()) return s;
  }
  return {};
}

bool graph_matches(const graph::Graph& g, const symbolic::World& world, const State& expected, std::string& why) {
  symbolic::World now = symbolic::read_world(g, world.vocabulary.types());
  // now's indices -> expected's
  std::vector<NodeIx> to_plan(now.ids.size(), kNoNode);
  for (NodeIx i = 0; i < now.ids.size(); ++i)
    for (NodeIx n = 0; n < world.ids.size(); ++n)
      if (n < expected.size() && expected.alive(n) && world.ids[n] == now.ids[i]) to_plan[i] = n;
  for (NodeIx i = 0; i < now.ids.size(); ++i) {
    if (to_plan[i] == kNoNode) {
      why = "the graph has node " + now.names[i] + " that the plan does not";
      return false;
    }
    const NodeIx n = to_plan[i];
    if (now.vocabulary.type_name(now.state.type(i)) != world.vocabulary.type_name(expected.type(n))) {
      why = "node " + now.names[i] + " is a " + now.vocabulary.type_name(now.state.type(i)) + ", the plan says " +
            world.vocabulary.type_name(expected.type(n));
      return false;
    }
  }
  if (now.state.alive_count() != expected.alive_count()) {
    why = "the graph has " + std::to_string(now.state.alive_count()) + " nodes, the plan " +
          std::to_string(expected.alive_count());
    return false;
  }
  std::set<std::tuple<NodeIx, std::string, NodeIx>> got, want;
  for (const Edge& e : now.state.edges()) got.emplace(to_plan[e.from], now.vocabulary.label_name(e.label), to_plan[e.to]);
  for (const Edge& e : expected.edges()) want.emplace(e.from, world.vocabulary.label_name(e.label), e.to);
  if (got != want) {
    for (const auto& [a, l, b] : want)
      if (!got.count({a, l, b})) {
        why = "link " + world.label(a) + " -[" + l + "]-> " + world.label(b) + " is missing from the graph";
        return false;
      }
    for (const auto& [a, l, b] : got)
      if (!want.count({a, l, b})) {
        why = "the graph has link " + world.label(a) + " -[" + l + "]-> " + world.label(b) + " that the plan does not";
        return false;
      }
  }
  return true;
}

Status verify_plan(graph::Graph& g, const GrammarChecker& checker, symbolic::World world, const PlanResult& plan,
                   const Mission& mission) {
  if (plan.states.size() != plan.steps.size() + 1)
    return make_error(ErrorCode::kInvalidArgument, "verify_plan(): the plan has no states (not found?)");
  // Each step is checked as the application of ITS rule (a change may also read as another
  // rule's, e.g. a passive rule's that says the same more loosely).
  RuleMatch claim;
  g.set_commit_validator([&](const graph::Graph& gg, const std::vector<graph::TxnOp>& ops) {
    return checker.verify(gg, ops, claim);
  });
  Status result;
  for (std::size_t i = 0; i < plan.steps.size() && result.ok(); ++i) {
    const Step& step = plan.steps[i];
    const std::string what = "step " + std::to_string(i + 1) + " (" + to_string(step, world) + ")";
    // Nodes the step reads by their ids before the change (a retyped node keeps its old id in
    // the claim); the nodes it creates by their new ids.
    std::vector<std::pair<std::string, graph::NodeId>> before_ids;
    for (const auto& [var, n] : step.binding)
      if (n < world.ids.size() && n < plan.states[i].size() && plan.states[i].alive(n))
        before_ids.emplace_back(var, world.ids[n]);
    auto tx = g.begin();
    Status s = write_change(tx, world, plan.states[i], plan.states[i + 1]);
    if (!s.ok()) {
      tx.abort();
      result = make_error(ErrorCode::kRefused, what + ": cannot be written: " + s.error().message);
      break;
    }
    claim = RuleMatch{step.name, {}};
    for (const auto& entry : step.binding) {
      const auto& var = entry.first;
      const auto n = entry.second;
      auto old = std::find_if(before_ids.begin(), before_ids.end(), [&](const auto& p) { return p.first == var; });
      claim.binding.emplace_back(var, old != before_ids.end() ? old->second : world.ids[n]);
    }
    std::sort(claim.binding.begin(), claim.binding.end());
    auto c = tx.commit();
    if (!c.ok()) {
      result = make_error(ErrorCode::kRefused, what + ": the grammar guard refuses it: " + c.error().message);
      break;
    }
    std::string why;
    if (!graph_matches(g, world, plan.states[i + 1], why))
      result = make_error(ErrorCode::kRefused, what + ": the graph differs from the plan's state: " + why);
  }
  g.set_commit_validator(nullptr);
  if (!result.ok()) return result;
  MissionReport r = check_mission(mission, g, world.vocabulary.types());
  if (!r.holds) {
    std::string m = "after the plan the mission does not hold:";
    for (const std::string& line : r.missing) m += " " + line + ";";
    return make_error(ErrorCode::kRefused, m);
  }
  return {};
}

Result<Step> parse_step(std::string_view text, const Domain& d, const symbolic::World& world) {
  auto bad = [&](const std::string& why) {
    return make_error(ErrorCode::kMalformed, "parse_step(): '" + std::string(text) + "': " + why);
  };
  std::string_view t = text;
  while (!t.empty() && (t.front() == ' ' || t.front() == '#' || t.front() == '!')) t.remove_prefix(1);
  Step step;
  if (!t.empty() && t.front() == '*') {
    step.hierarchical = true;
    t.remove_prefix(1);
  }
  const auto at = t.find('@');
  if (at == std::string_view::npos) return bad("expected rule@{...}");
  step.name = std::string(t.substr(0, at));
  const auto& names = d.rule_names();
  auto it = std::find(names.begin(), names.end(), step.name);
  if (it == names.end()) return bad("no active rule '" + step.name + "' in the domain");
  step.rule = static_cast<int>(it - names.begin());
  step.hierarchical = d.hierarchical(step.rule);
  std::string_view rest = t.substr(at + 1);
  if (rest.empty() || rest.front() != '{' || rest.back() != '}') return bad("expected {...} after '@'");
  rest = rest.substr(1, rest.size() - 2);
  // 'var': 'label', ...
  auto quoted = [&](std::string_view& s, std::string& out) {
    while (!s.empty() && (s.front() == ' ' || s.front() == ',')) s.remove_prefix(1);
    if (s.empty() || (s.front() != '\'' && s.front() != '"')) return false;
    const char q = s.front();
    const auto end = s.find(q, 1);
    if (end == std::string_view::npos) return false;
    out = std::string(s.substr(1, end - 1));
    s.remove_prefix(end + 1);
    return true;
  };
  for (;;) {
    while (!rest.empty() && (rest.front() == ' ' || rest.front() == ',')) rest.remove_prefix(1);
    if (rest.empty()) break;
    std::string var, label;
    if (!quoted(rest, var)) return bad("expected a quoted variable");
    while (!rest.empty() && rest.front() == ' ') rest.remove_prefix(1);
    if (rest.empty() || rest.front() != ':') return bad("expected ':' after '" + var + "'");
    rest.remove_prefix(1);
    if (!quoted(rest, label)) return bad("expected a quoted node after '" + var + "'");
    // A node the step creates has no node yet: Domain::apply() binds it.
    step.binding.emplace_back(var, world.find(label));
  }
  std::sort(step.binding.begin(), step.binding.end());
  return step;
}

}  // namespace quiver::agents::inline rules::planner
