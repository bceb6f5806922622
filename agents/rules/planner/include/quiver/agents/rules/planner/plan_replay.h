#pragma once
/// @file
/// Plans on a real replica: a step written as one transaction, a plan replayed step by step
/// through the grammar guard (every step must be accepted as one application of its rule, and
/// leave the graph exactly as the planner predicted), and plan steps as text.

#include <string>
#include <string_view>
#include <vector>

#include "quiver/agents/rules/grammar/grammar.h"
#include "quiver/agents/rules/mission/mission.h"
#include "quiver/agents/rules/planner/domain.h"
#include "quiver/agents/rules/planner/planner.h"
#include "quiver/graph/graph.h"

namespace quiver::agents::inline rules::planner {

/// Writes the change from `before` to `after` (states over `world`'s nodes) into `tx`: retypes
/// first (replace_node_type), then created nodes (named `<type>_<AGM id>` with `agm_id` when the
/// world has AGM ids, else their label `new_<index>`, made unique), deleted nodes, removed and added links
/// (label RT: the RT tree, identity pose). `world` learns the new nodes' ids, names and labels.
/// @returns the error of the transaction call that failed (abort `tx` then).
Status write_change(graph::Transaction& tx, symbolic::World& world, const symbolic::State& before,
                    const symbolic::State& after);

/// True if `g` holds exactly `expected` (nodes by `world.ids`, types, links); otherwise false
/// with the first difference in `why`.
bool graph_matches(const graph::Graph& g, const symbolic::World& world, const symbolic::State& expected,
                   std::string& why);

/// Replays `plan` (found from `world`'s state, which `g` holds) on `g`: every step one
/// transaction that `checker` must accept as an application of the step's rule and that must
/// leave `g` as plan.states predicts; at the end `mission` must hold in `g`.
/// @returns kRefused naming the step and what failed.
Status verify_plan(graph::Graph& g, const GrammarChecker& checker, symbolic::World world, const PlanResult& plan,
                   const Mission& mission);

/// Parses "rule@{'var': 'label', ...}" (AGM's plan line; labels as World::label) into a step
/// of `d` over `world`'s nodes. A leading '*' (hierarchical) is accepted.
Result<Step> parse_step(std::string_view text, const Domain& d, const symbolic::World& world);

}  // namespace quiver::agents::inline rules::planner
