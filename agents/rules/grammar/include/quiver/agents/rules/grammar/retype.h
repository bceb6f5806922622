#pragma once
/// @file
/// Retyping a node, as AGM's rules do (`x:unknownObject` on the left, `x:mug` on the right).
///
/// A node's type is fixed when it is created: replicas agree on it without a register to merge.
/// So a retype is a replacement: in one transaction the node is deleted and a node of the new
/// type is created under the same name, with the old one's attributes, symbolic edges (self-loops
/// included) and RT links. The grammar checker reads such a pair as one retyped node
/// (docs/grammar.md, "Retyping"). The new node has a new id: code that keeps node ids across
/// changes should look the node up by name again.

#include <string_view>

#include "quiver/graph/graph.h"
#include "quiver/base/result.h"

namespace quiver::agents::inline rules {

/// Adds to `tx` the replacement of `node` by a node of `type` with the same name, attributes,
/// edges and RT links (the RT pose of each link at its newest sample).
/// @pre `node` is visible in `tx.graph()` and `tx` has not changed it or its edges yet.
/// @returns the new node's id, or the error of the transaction call that failed (the
///   transaction then holds part of the replacement: abort it).
Result<graph::NodeId> replace_node_type(graph::Transaction& tx, graph::NodeId node,
                                        std::string_view type);

}  // namespace quiver::agents
