#pragma once
/// @file
/// The planner agent: one agent among others (no executive). It reads a mission (given, or the
/// `mission` attribute of the plan node), plans from its replica with a domain grammar, and
/// writes the plan into the graph as attributes of the plan node for the agents that execute
/// the steps. Then it watches: on every change it finds how far the world has come along the
/// plan (the first step from which the rest of the plan still applies and reaches the mission),
/// and when no rest does any more - the world deviated - it plans again from where the world is.
///
/// The plan node (type `plan`, name PlannerAgentOptions::plan_node) carries:
///   `steps`    string, one step per line as AGM prints them: `rule@{'var': 'node', ...}`
///   `next`     int, the index of the next step to execute
///   `status`   string: "executing", "achieved", "failed: why"
///   `version`  int, incremented by every new plan
///   `replans`  int, plans made because the world deviated
///   `cost`, `expansions`
/// The agent writes nothing else; everything it knows is in the graph, so a restarted planner
/// continues from it. Deterministic (no wall clock: the search is bounded by expansions).

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "quiver/agents/rules/planner/planner.h"
#include "quiver/agents/runtime/api/agent.h"

namespace quiver::agents::inline apps::planning {

struct PlannerAgentOptions {
  /// The domain: AGGL text (AGM's dialect or ours; no include) and the name it is known by.
  std::string domain_text, domain_source = "domain.aggl";
  /// The mission (.aggt text). Empty: read from the plan node's `mission` attribute.
  std::string mission_text, mission_source = "mission.aggt";
  std::string plan_node = "plan";
  /// Nodes the planner does not see (with their edges): a team's robot plans for itself, without
  /// the other robots and what they carry. Empty: it sees the whole graph.
  std::function<bool(const graph::Graph&, graph::NodeId)> hide;
  /// The search; bounded by expansions (deterministic) so that one plan never holds the agent's
  /// thread for long: 200k expansions are well under a second on the public AGM domains.
  planner::PlannerOptions planner = [] {
    planner::PlannerOptions o;
    o.max_expansions = 200'000;
    return o;
  }();
  /// How often it looks at the world again when something changed.
  std::int64_t period_ns = 50'000'000;
  /// Called at the end of setup() and of status(): what an embedding adds to the agent (e.g. a
  /// latency probe subscribing to changes, and its figures in the status line).
  std::function<void(Agent&, AgentContext&)> on_setup;
  std::function<void(nlohmann::json&)> on_status;
};

class PlannerAgent final : public Agent {
 public:
  explicit PlannerAgent(PlannerAgentOptions o, std::string name = "mission_planner");
  ~PlannerAgent() override;
  void setup(AgentContext& ctx) override;
  void status(nlohmann::json& out) const override;

  std::uint64_t plans() const { return plans_; }
  std::uint64_t replans() const { return replans_; }

 private:
  void think(AgentContext& ctx);
  struct Impl;
  std::unique_ptr<Impl> impl_;
  PlannerAgentOptions opt_;
  bool dirty_ = true;
  std::uint64_t plans_ = 0, replans_ = 0;
  std::string state_;
};

/// An agent that executes plan steps (for simulations, demos and tests): whenever the plan
/// node asks for a step it has not done yet, it waits `step_ns` (the action takes time), then
/// applies the step to its replica as one transaction under its grammar (the domain), unless the
/// step no longer applies (the planner will see that and plan again).
struct StepExecutorOptions {
  std::string domain_text, domain_source = "domain.aggl";
  std::string plan_node = "plan";
  std::int64_t step_ns = 500'000'000;
};

class StepExecutor final : public Agent {
 public:
  explicit StepExecutor(StepExecutorOptions o, std::string name = "executor");
  ~StepExecutor() override;
  void setup(AgentContext& ctx) override;
  std::uint64_t executed() const { return executed_; }
  /// Plan versions it executed steps of.
  const std::vector<std::int64_t>& versions() const { return versions_; }

 private:
  void execute(AgentContext& ctx, std::int64_t version, std::int64_t next);
  StepExecutorOptions opt_;
  std::unique_ptr<Grammar> grammar_;
  std::int64_t done_version_ = -1, done_next_ = -1;
  bool busy_ = false;
  std::uint64_t executed_ = 0;
  std::vector<std::int64_t> versions_;
};

/// Reads an int/string attribute of the plan node (helpers for agents that follow plans).
std::optional<graph::NodeId> find_plan_node(const graph::Graph& g, const std::string& name = "plan");

}  // namespace quiver::agents::inline apps::planning
