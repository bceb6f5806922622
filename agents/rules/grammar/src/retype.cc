// Retyping a node as a replacement: a node of the new type under the same name, with the old one's attributes,
// edges and RT links, in the same transaction.
#include "quiver/agents/rules/grammar/retype.h"

namespace quiver::agents::inline rules {

using graph::EdgeKey;
using graph::NodeId;
using graph::Symbol;
using graph::Value;

Result<NodeId> replace_node_type(graph::Transaction& tx, NodeId node, std::string_view type) {
  const graph::Graph& g = tx.graph();
  if (!g.has_node(node))
    return make_error(ErrorCode::kNotFound,
                      "replace_node_type(): node " + node.to_string() + " does not exist");
  const std::string name = g.name_of(node);
  std::vector<std::pair<Symbol, Value>> attrs;
  for (Symbol a : g.attr_names(node))
    if (const Value* v = g.attr(node, a)) attrs.emplace_back(a, *v);
  struct Edge {
    EdgeKey key;
    std::vector<std::pair<Symbol, Value>> attrs;
  };
  std::vector<Edge> edges;
  const Symbol rt = graph::symbols::rt();
  auto keep = [&](const EdgeKey& k) {
    if (k.type == rt) return;
    for (const Edge& e : edges)
      if (e.key == k) return;  // a self-loop is listed both ways
    Edge e{k, {}};
    for (Symbol a : g.edge_attr_names(k))
      if (const Value* v = g.edge_attr(k, a)) e.attrs.emplace_back(a, *v);
    edges.push_back(std::move(e));
  };
  for (const EdgeKey& k : g.edges_from(node)) keep(k);
  for (const EdgeKey& k : g.edges_to(node)) keep(k);
  const std::optional<graph::RtEdge> up = g.rt_edge(node);
  std::vector<graph::RtEdge> down;
  for (NodeId c : g.rt_children(node))
    if (auto e = g.rt_edge(c)) down.push_back(*e);

  if (Status s = tx.delete_node(node); !s.ok()) return s.error();
  Result<NodeId> fresh = tx.create_node(type, name, std::move(attrs));
  if (!fresh.ok()) return fresh;
  auto as_new = [&](NodeId n) { return n == node ? *fresh : n; };
  for (Edge& e : edges)
    if (Status s =
            tx.insert_edge(as_new(e.key.from), as_new(e.key.to), e.key.type, std::move(e.attrs));
        !s.ok())
      return s.error();
  if (up)
    if (Status s = tx.set_rt(up->parent, *fresh, up->pose, up->stamp); !s.ok()) return s.error();
  for (const graph::RtEdge& e : down)
    if (Status s = tx.set_rt(*fresh, e.child, e.pose, e.stamp); !s.ok()) return s.error();
  return fresh;
}

}  // namespace quiver::agents
