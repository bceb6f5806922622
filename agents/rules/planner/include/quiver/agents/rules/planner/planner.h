#pragma once
/// @file
/// Finding a sequence of active rules that takes a symbolic state to one where a mission holds
/// (docs/planner.md).
///
/// A* over symbolic states: g is AGM's plan cost (domain.h, plan_cost), h a lower bound on the
/// cost still to pay (heuristic()), states deduplicated exactly (hash, then equality). The plan
/// it returns is optimal among plans whose states keep within the growth bound, when every
/// rule's success probability is 1 and the domain has no hierarchical rules (a hierarchical step
/// is searched at its declared cost, then decomposed). Deterministic: rules in the grammar's
/// order, matches in node order, ties broken by depth then generation order.
///
/// Hierarchical steps are decomposed as AGM does, but every one of them (AGM refines only the
/// first): a sub-search from the state before the step, towards the step rule's right-hand side
/// with the step's nodes fixed, without that rule; then the rest of the plan is searched again
/// from where the decomposition left the world.

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "quiver/agents/rules/mission/mission.h"
#include "quiver/agents/rules/planner/domain.h"

namespace quiver::agents::inline rules::planner {

struct PlannerOptions {
  /// A state may hold at most this many nodes more than the start (AGM's maxWorldIncrement).
  int max_world_increment = 5;
  /// Expansions before giving up (deterministic; 0: no limit).
  std::size_t max_expansions = 5'000'000;
  /// Time limit in ns (0: none), measured with `clock` (required then): no wall clock is read
  /// unless the caller injects one.
  std::int64_t max_time_ns = 0;
  std::function<std::int64_t()> clock;
  /// false: h = 0 (uniform-cost search), for tests of the heuristic.
  bool heuristic = true;
  /// Decompose hierarchical steps into plans of other rules.
  bool decompose = true;
  /// Nesting of decompositions (a hierarchical step inside a decomposition, ...).
  int max_decomposition_depth = 8;
};

struct PlanResult {
  enum class Outcome : std::uint8_t {
    kFound,       ///< steps reach the mission (empty if it already held)
    kExhausted,   ///< every state within the growth bound was searched: no plan
    kLimit,       ///< max_expansions or max_time_ns was reached first
    kUnsolvable,  ///< the heuristic proves no rule sequence can reach it (or a constant is unknown)
  };
  Outcome outcome = Outcome::kExhausted;
  bool found() const { return outcome == Outcome::kFound; }
  std::vector<Step> steps;
  /// states[0] is the start, states[i + 1] the state after steps[i].
  std::vector<symbolic::State> states;
  double cost = 0;              ///< plan_cost(steps)
  /// The cost of the top-level plan as searched, hierarchical steps at their declared cost
  /// (what AGM's planner reports); equal to `cost` without hierarchical steps.
  double search_cost = 0;
  std::size_t expansions = 0;   ///< states expanded (all searches)
  std::size_t generated = 0;    ///< successor states generated
  std::size_t searches = 0;     ///< 1 + decompositions and re-searches
  std::string why;              ///< when not found: what stopped it
};

const char* to_string(PlanResult::Outcome o);

/// Plans from `start` to `mission` with the active rules of `domain`.
PlanResult plan(const Domain& domain, const symbolic::State& start, const CompiledMission& mission,
                const PlannerOptions& options = {});

/// The heuristic: a lower bound on the cost of reaching `mission` from `s`, or +inf when no
/// rule sequence can. For every link label the mission lacks links of (counting only links no
/// existing link of that label could stand for), at least ceil(lacking / most added by one
/// application) applications of rules adding that label are needed, each costing at least the
/// cheapest of them; likewise for negated links present (rules removing the label or deleting
/// nodes) and for nodes (more variables of a type than nodes of it: rules creating or retyping
/// to it). h is the largest of these bounds (one application may serve several), so it never
/// overestimates: A* with it returns optimal plans.
double heuristic(const Domain& domain, const symbolic::State& s, const CompiledMission& mission);

}  // namespace quiver::agents::inline rules::planner
