#pragma once
/// @file
/// A starting schema from what a world holds (`quiver schema infer`): every node type, every edge
/// type with the node types seen at its ends, every attribute with the value type it holds
/// ("any" when it holds several). Nothing is inferred that the world does not show: no
/// inheritance, no units, ranges, holders or writers; the file is the user's to refine.

#include "quiver/agents/rules/schema/schema.h"
#include "quiver/graph/graph.h"

namespace quiver::agents::inline rules::schema {

/// Adds to `s` what `g` holds (declarations already in `s` are widened, never narrowed: an
/// attribute seen with another value type becomes "any", an edge's ends gain the types seen).
void infer_from_graph(const graph::Graph& g, Schema& s);

}  // namespace quiver::agents::inline rules::schema
