#pragma once
/// @file
/// A change seen as the policy's actions: a local transaction (with the graph it applies to), a
/// delta (everything in it is its origin's) or a state fragment (each entry is its writer's, the
/// replica of its dot).

#include <vector>

#include "quiver/agents/rules/permissions/policy.h"
#include "quiver/graph/delta.h"
#include "quiver/graph/graph.h"

namespace quiver::agents::inline rules::permissions {

/// Ok, or the first action of the transaction `ops` that `agent` may not take on `g`.
Status check_transaction(const Policy& p, std::uint64_t agent, const graph::Graph& g,
                         const std::vector<graph::TxnOp>& ops);
/// Ok, or the first action of the delta `d` its origin may not take.
Status check_delta(const Policy& p, const graph::GraphDelta& d);
/// Ok, or the first entry of the state fragment `s` that its writer may not have written.
/// Deletions leave nothing in a state: they are checked on deltas only.
Status check_state(const Policy& p, const graph::GraphDelta& s);

}  // namespace quiver::agents::inline rules::permissions
