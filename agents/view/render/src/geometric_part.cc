// The geometric part of a world graph, decided in one place: RT edges, and nodes that hang in the kinematic tree
// but take part in no symbolic edge.
#include "quiver/agents/view/render/geometric_part.h"

namespace quiver::agents::inline view::render {

bool is_geometric_edge_type(std::string_view type) { return type == graph::symbols::rt().str(); }

bool is_geometric(const graph::EdgeKey& key) { return key.type == graph::symbols::rt(); }

bool is_geometric(const graph::Graph& g, graph::NodeId id) {
  if (!g.has_node(id)) return false;
  bool rt = false;
  for (const auto& edges : {g.edges_from(id), g.edges_to(id)}) {
    for (const graph::EdgeKey& k : edges) {
      if (!is_geometric(k)) return false;  // a symbolic edge: never geometric
      rt = true;
    }
  }
  return is_geometric_node(/*symbolic_edges=*/false, rt);
}

}  // namespace quiver::agents::inline view::render
