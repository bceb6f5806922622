#pragma once
/// @file
/// "Hide the geometric part" of a world graph, as AGM's viewer does, decided in ONE place: the
/// pictures (`quiver render`), the timeline (`quiver timeline`) and the web viewer all call it.
///
/// The rule:
///  - an RT edge (type symbols::rt(), "RT": the kinematic tree) is geometry;
///  - a node is geometric when it takes part in no symbolic (non-RT) edge, in either direction,
///    but hangs in the kinematic tree: it has an RT parent or RT children.
///
/// So a body joint or a sensor frame that only has a pose disappears, while a node with both
/// kinds of edge (a robot `in` a room and also the RT child of the world) stays, without its RT
/// edges. A node with no edges at all is not geometric: it stays. The rule reads the visible
/// graph only (edges whose endpoints are both visible).

#include <string_view>

#include "quiver/graph/graph.h"

namespace quiver::agents::inline view::render {

/// The rule itself, for callers that hold their own copy of a graph (a page's script).
/// @param symbolic_edges whether the node takes part in any non-RT edge (either direction)
/// @param rt_edges whether it has an RT parent or RT children
/// @returns true when the node is geometric
constexpr bool is_geometric_node(bool symbolic_edges, bool rt_edges) {
  return !symbolic_edges && rt_edges;
}

/// Whether edges of this type are geometry (the RT type).
bool is_geometric_edge_type(std::string_view type);

/// Whether an edge is geometry (an RT edge).
bool is_geometric(const graph::EdgeKey& key);

/// Whether a node of `g` is geometric (see the rule above). False for a node `g` does not hold.
/// Cost: the node's incident edges.
bool is_geometric(const graph::Graph& g, graph::NodeId id);

}  // namespace quiver::agents::inline view::render
