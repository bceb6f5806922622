#pragma once
/// @file
/// What a subscriber is told (Graph::subscribe): the nodes and edges one commit or one merge
/// created, updated or deleted, and filters over them.
///
/// Threading: plain value types; ChangeFilter::select() and to_string() are thread-safe.

#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "quiver/graph/ids.h"
#include "quiver/graph/symbol.h"
#include "quiver/graph/value.h"

namespace quiver::graph {

enum class ChangeKind : std::uint8_t { kCreated, kUpdated, kDeleted };
/// @returns "created", "updated" or "deleted" (a static string); "unknown" for any other value.
/// Thread-safe.
const char* to_string(ChangeKind k);

/// A node created, deleted or updated. Updated: some attributes' values changed (attr_values():
/// another value written, a removal, a concurrent value arriving or going; rewriting the same
/// value is none, as in DSR), or its name changed (an earlier namesake came, the holder left).
struct NodeChange {
  NodeId id;
  ChangeKind kind;
  Symbol type;
  /// kCreated: every attribute the node has; kUpdated: those whose values changed.
  std::vector<Symbol> attrs;
  bool renamed = false;  ///< kUpdated: name_of() now returns something else
  /// kDeleted: what the node was when it went, as DSR's deletion signals carry the deleted node:
  /// its last name (name_of()) and attribute values (the winners, by name; empty otherwise).
  std::string name;
  std::vector<std::pair<Symbol, Value>> values;
};
/// An edge created, deleted or updated. A symbolic edge is updated when its attributes' values
/// or its version (edge_version(): a re-insert) changed; an RT edge when its current transform
/// or the pose history of its current move changed (attrs then holds "pose") or its attributes
/// changed (attrs names them; they are kept on the child as rt:<name>, whose node change names
/// them too). An RT edge that changes parent is deleted under the old parent and created under
/// the new one.
struct EdgeChange {
  EdgeKey key;  ///< RT edges appear with type symbols::rt(), from parent to child.
  ChangeKind kind;
  std::vector<Symbol> attrs;  ///< kCreated: every attribute; kUpdated: those that changed
  /// kDeleted: a symbolic edge's last attribute values (the winners); an RT edge's last pose
  /// ("translation": x, y, z; "rotation": the quaternion w, x, y, z, both DoubleVec) and
  /// attributes.
  std::vector<std::pair<Symbol, Value>> values;
};
/// Everything one commit or one merge changed in the visible graph.
struct ChangeBatch {
  bool local = false;
  ReplicaId origin;  ///< the replica whose change this is (this replica's id when local)
  /// The name of the agent whose change this is, as the graph's origin namer tells it (a
  /// replicator installs one that knows the names peers announce); origin.to_string() when the
  /// origin is unknown or no namer is installed.
  std::string origin_name;
  std::vector<NodeChange> nodes;
  std::vector<EdgeChange> edges;
  /// @returns true if the batch lists no node and no edge change.
  bool empty() const { return nodes.empty() && edges.empty(); }
};
using ChangeCallback = std::function<void(const ChangeBatch&)>;

/// Which changes a subscription cares about: a node change whose node type is listed, an edge
/// change whose edge type is listed, or a node or edge change that names a listed attribute.
/// The lists are alternatives (a change passes if any list lets it through); an empty list lets
/// nothing through by itself, and a filter with all lists empty lets everything through.
struct ChangeFilter {
  std::vector<std::string> node_types;
  std::vector<std::string> edge_types;
  std::vector<std::string> attributes;

  /// @returns true if all three lists are empty (the filter lets everything through).
  bool empty() const { return node_types.empty() && edge_types.empty() && attributes.empty(); }
  /// The part of `b` this filter lets through (origin and locality copied). Empty when nothing
  /// matches.
  /// @returns `b` itself when the filter is empty(); otherwise the changes it selects, in `b`'s
  ///          order, with `b`'s local, origin and origin_name.
  ChangeBatch select(const ChangeBatch& b) const;
};

}  // namespace quiver::graph
