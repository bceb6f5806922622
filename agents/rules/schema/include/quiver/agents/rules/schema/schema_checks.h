#pragma once
/// @file
/// A change checked against the schema: a local transaction (with the graph it applies to: the
/// ends of an edge are known there), a delta (everything in it is its origin's; the types it
/// checks are the ones it states) or a state fragment (each entry is its writer's). A received
/// delta or state is judged on itself and the schema alone, never on what the receiver holds,
/// so that every replica decides alike and replicas that refuse it stay equal.

#include <cstdint>
#include <vector>

#include "quiver/agents/rules/schema/schema.h"
#include "quiver/graph/delta.h"
#include "quiver/graph/graph.h"

namespace quiver::agents::inline rules::schema {

/// Ok, or the first change of the transaction `ops` by `agent` on `g` that the schema refuses.
Status check_transaction(const Schema& s, std::uint64_t agent, const graph::Graph& g,
                         const std::vector<graph::TxnOp>& ops);
/// Ok, or the first change of the delta `d` the schema refuses.
Status check_delta(const Schema& s, const graph::GraphDelta& d);
/// Ok, or the first entry of the state fragment `st` the schema refuses.
Status check_state(const Schema& s, const graph::GraphDelta& st);

}  // namespace quiver::agents::inline rules::schema
