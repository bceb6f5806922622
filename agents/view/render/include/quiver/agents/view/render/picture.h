#pragma once
/// @file
/// What a picture of a world graph shows, before any layout: the visible nodes (label
/// "name\n(type)", filled with their type's colour), the edges (labelled by type; RT edges
/// dashed grey), which of them are highlighted, and an optional title. The renderers
/// (render.h) and the timeline (timeline.h) lay it out with Graphviz (layout.h).

#include <cstddef>
#include <string>
#include <unordered_set>
#include <vector>

#include "quiver/graph/graph.h"

namespace quiver::agents::inline view::render {

struct PictureOptions {
  /// Leave out the geometric part (geometric_part.h): RT edges and geometric nodes.
  bool hide_geometry = false;
  /// Drawn bold in the highlight colour (when shown).
  std::unordered_set<graph::NodeId> highlight_nodes;
  std::unordered_set<graph::EdgeKey> highlight_edges;
  /// A line above the picture ("" for none).
  std::string title;
};

struct PictureNode {
  graph::NodeId id;
  std::string name;
  std::string type;
  bool geometric = false;  ///< drawn as a box (a frame of the kinematic tree), else an ellipse
  bool highlighted = false;
};

struct PictureEdge {
  graph::EdgeKey key;
  std::size_t from = 0;  ///< index into Picture::nodes
  std::size_t to = 0;
  std::string type;
  bool geometric = false;  ///< an RT edge: dashed grey
  bool highlighted = false;
};

struct Picture {
  std::vector<PictureNode> nodes;  ///< sorted by name
  std::vector<PictureEdge> edges;  ///< sorted by (from name, to name, type)
  std::string title;
};

/// The picture of `g`'s visible graph under `options`. Deterministic: equal graphs give equal
/// pictures whatever their replicas' histories.
Picture make_picture(const graph::Graph& g, const PictureOptions& options = {});

/// The label Graphviz and the PNG renderer show for a node: "name\n(type)".
std::string node_label(const PictureNode& n);

}  // namespace quiver::agents::inline view::render
