// The clean-the-table mission: its goal, its grammar, and the report on a replica's plan.
#include "quiver/agents/apps/agm/clean_table.h"

#include "quiver/agents/apps/agm/agm_schema.h"
#include "quiver/agents/rules/grammar/grammar.h"
#include "quiver/agents/rules/mission/mission.h"
#include "quiver/agents/rules/planner/plan_replay.h"
#include "quiver/graph/world_file.h"

namespace quiver::agents::inline apps::agm {

namespace {

template <class T>
T attr_or(const graph::Graph& g, graph::NodeId n, const char* name, T fallback) {
  const graph::Value* v = n.is_null() ? nullptr : g.attr(n, name);
  const T* p = v ? v->get_if<T>() : nullptr;
  return p ? *p : fallback;
}

}  // namespace

CleanTableReport check_clean_table(const graph::Graph& g) {
  CleanTableReport r;
  auto domain = parse_grammar(embedded_file("clean_table.aggl"), "clean_table.aggl");
  auto mission = parse_mission(embedded_file("clean-table.aggt"), "clean-table.aggt");
  if (!domain.ok() || !mission.ok()) {
    r.missing.push_back(!domain.ok() ? domain.error().to_string() : mission.error().to_string());
    return r;
  }
  MissionReport m = check_mission(*mission, g, domain->types);
  r.mission_holds = m.holds;
  r.missing = m.missing;
  const graph::NodeId plan = node_id(g, "plan");
  r.plan_status = attr_or<std::string>(g, plan, "status", "");
  r.steps = attr_or<std::string>(g, plan, "steps", "");
  r.version = attr_or<std::int64_t>(g, plan, "version", 0);
  r.replans = attr_or<std::int64_t>(g, plan, "replans", 0);
  r.next = attr_or<std::int64_t>(g, plan, "next", 0);
  return r;
}

Status verify_clean_table_plan(const std::string& steps) {
  auto grammar = parse_grammar(embedded_file("clean_table.aggl"), "clean_table.aggl");
  if (!grammar.ok()) return grammar.error();
  auto mission = parse_mission(embedded_file("clean-table.aggt"), "clean-table.aggt");
  if (!mission.ok()) return mission.error();
  graph::Graph g(graph::ReplicaId{0x636c65616eULL, 1});
  if (auto w = graph::load_world(g, embedded_file("clean-table.json"), "clean-table.json"); !w.ok())
    return w.error();
  symbolic::World world = symbolic::read_world(g, grammar->types);
  planner::Domain domain(*grammar, world.vocabulary);
  planner::PlanResult plan;
  plan.outcome = planner::PlanResult::Outcome::kFound;
  plan.states.push_back(world.state);
  std::size_t start = 0;
  while (start < steps.size()) {
    std::size_t end = steps.find('\n', start);
    if (end == std::string::npos) end = steps.size();
    const std::string line = steps.substr(start, end - start);
    start = end + 1;
    if (line.empty()) continue;
    auto step = planner::parse_step(line, domain, world);
    if (!step.ok()) return step.error();
    auto after = domain.apply(plan.states.back(), *step);
    if (!after)
      return make_error(ErrorCode::kRefused, "step " + line + " does not apply in the domain");
    plan.steps.push_back(*step);
    plan.states.push_back(std::move(*after));
  }
  GrammarChecker checker(*grammar);
  return planner::verify_plan(g, checker, world, plan, *mission);
}

}  // namespace quiver::agents::inline apps::agm
