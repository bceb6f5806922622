#pragma once
/// @file
/// The world model as the viewer's page sees it: JSON for nodes (type, colour, attributes with
/// every concurrent value and its writer, RT parent and pose, collision shape, images, lock),
/// symbolic edges, and the messages that carry changes. The page's protocol is in
/// docs/viewer.md ("The page's protocol").

#include <functional>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "quiver/graph/graph.h"

namespace quiver::agents::inline view::viewer {

/// What the viewer knows beyond the graph: who is behind a replica id, which scopes are locked
/// and by whom, which nodes take part in a grammar violation.
struct Decor {
  std::function<std::string(const graph::ReplicaId&)> name_of;  ///< null: ids as text
  struct Lock {
    std::string holder;
    std::uint64_t epoch = 0;
    std::int64_t priority = 0;
  };
  std::map<graph::NodeId, Lock> locks;
  /// Open violations: a constraint and its binding (variable -> node).
  std::vector<std::pair<std::string, std::vector<std::pair<std::string, graph::NodeId>>>> violations;
};

/// The id of a node as the page names it.
std::string node_key(graph::NodeId id);

nlohmann::json node_json(const graph::Graph& g, graph::NodeId id, const Decor& d);
nlohmann::json edge_json(const graph::Graph& g, const graph::EdgeKey& k, const Decor& d);
/// An RT edge's pose as {"id", "parent", "t": [x,y,z], "q": [w,x,y,z], "stamp"}; null if none.
nlohmann::json pose_json(const graph::Graph& g, graph::NodeId child);
nlohmann::json violations_json(const Decor& d);

/// The whole graph: {"nodes": [...], "edges": [...], "violations": [...], "types": {name: colour}}.
nlohmann::json snapshot_json(const graph::Graph& g, const Decor& d);

/// Changes gathered between two messages: what to send again in full, what went, which poses
/// moved. Fed with change batches; drained into a message.
class ChangeAccumulator {
 public:
  void add(const graph::ChangeBatch& b);
  bool empty() const { return nodes_.empty() && gone_nodes_.empty() && edges_.empty() && gone_edges_.empty() && poses_.empty(); }
  /// {"nodes": [...], "deleted_nodes": [...], "edges": [...], "deleted_edges": [...], "poses":
  /// [...]}: each changed thing as it is now in `g` (a node deleted since is listed as deleted).
  nlohmann::json drain(const graph::Graph& g, const Decor& d);

 private:
  struct EdgeLess {
    bool operator()(const graph::EdgeKey& a, const graph::EdgeKey& b) const { return graph::canonical_less(a, b); }
  };
  std::set<graph::NodeId> nodes_, gone_nodes_, poses_;
  std::set<graph::EdgeKey, EdgeLess> edges_, gone_edges_;
};

/// One line per recorded change for the timeline: {"created": ["name (type)"], "deleted": [...],
/// "updated": ["name: attr, attr"], "edges_created": ["a -[t]-> b"], "edges_deleted": [...],
/// "poses": n}. `g` is the graph after the batch (deleted nodes are named by id).
nlohmann::json summary_json(const graph::Graph& g, const graph::ChangeBatch& b);

}  // namespace quiver::agents::inline view::viewer
