#pragma once
// Private: the visible graph as both exporters walk it — nodes with the ids the file will use,
// attributes split into the node's own and its RT link's (`rt:` prefix), RT parents with their
// poses, symbolic edges — in one deterministic order (ids ascending).

#include <array>
#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "quiver/graph/graph.h"

namespace quiver::interop::internal {

using AttrRefs = std::vector<std::pair<std::string, const graph::Value*>>;

struct ExportNode {
  graph::NodeId id;
  std::string name, type;
  std::string file_id;   ///< the id written to the file
  bool own_id = false;   ///< file_id came from the node's id attribute
  AttrRefs attrs;        ///< the node's attributes but the consumed ones and the RT link's
  AttrRefs rt_attrs;     ///< `rt:<name>` attributes, without the prefix (only under an RT parent)
  std::optional<std::size_t> parent;  ///< index of the RT parent
  graph::Pose pose;                   ///< X_PC when there is a parent
  std::array<double, 3> t{}, r{};     ///< the same in the formats' convention and unit (euler_xyz.h)
  int depth = 0;                      ///< depth in the RT tree (0 for a root or a loose node)
  std::vector<std::size_t> edges;     ///< indices into ExportView::edges of the edges from it
};

struct ExportEdge {
  std::size_t from = 0, to = 0;
  std::string type;
  AttrRefs attrs;
};

struct ExportView {
  std::vector<ExportNode> nodes;
  std::vector<ExportEdge> edges;
  std::vector<std::string> warnings;
};

struct IdPolicy {
  /// The node attribute that holds the source id (dsr_id, agm_id); consumed.
  std::string attr;
  /// Other attributes the format writes elsewhere (agm_x, agm_y); consumed.
  std::vector<std::string> consumed;
  /// The id text of the id attribute's value, or nullopt when the format cannot use it.
  std::function<std::optional<std::string>(const graph::Value&)> id_of;
  /// What the ids are called in warnings ("CORTEX id", "AGM id").
  std::string what;
};

/// Nodes with usable, unique ids keep them; the others (ordered by name) get fresh numbers
/// above the largest numeric id. Nodes are ordered by id (numbers first, ascending).
/// Poses are given in units of `metres_per_unit` metres.
ExportView make_export_view(const graph::Graph& g, const IdPolicy& policy, double metres_per_unit);

}  // namespace quiver::interop::internal
