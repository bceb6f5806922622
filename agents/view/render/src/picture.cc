// What a picture of a world graph shows before any layout: the visible nodes and edges, the highlighted ones and
// a title.
#include "quiver/agents/view/render/picture.h"

#include <algorithm>
#include <unordered_map>

#include "quiver/agents/view/render/geometric_part.h"

namespace quiver::agents::inline view::render {

Picture make_picture(const graph::Graph& g, const PictureOptions& options) {
  Picture p;
  p.title = options.title;
  for (graph::NodeId id : g.nodes()) {
    const bool geometric = is_geometric(g, id);
    if (options.hide_geometry && geometric) continue;
    p.nodes.push_back(PictureNode{id, g.name_of(id), g.type_of(id).str(), geometric,
                                  options.highlight_nodes.contains(id)});
  }
  std::sort(p.nodes.begin(), p.nodes.end(),
            [](const PictureNode& a, const PictureNode& b) { return a.name < b.name; });
  std::unordered_map<graph::NodeId, std::size_t> index;
  for (std::size_t i = 0; i < p.nodes.size(); ++i) index.emplace(p.nodes[i].id, i);

  for (std::size_t i = 0; i < p.nodes.size(); ++i) {
    for (const graph::EdgeKey& k : g.edges_from(p.nodes[i].id)) {
      const bool geometric = is_geometric(k);
      if (options.hide_geometry && geometric) continue;
      auto to = index.find(k.to);
      if (to == index.end()) continue;
      p.edges.push_back(PictureEdge{k, i, to->second, k.type.str(), geometric,
                                    options.highlight_edges.contains(k)});
    }
  }
  // Nodes are sorted by name, so indices order edges by endpoint names.
  std::sort(p.edges.begin(), p.edges.end(), [](const PictureEdge& a, const PictureEdge& b) {
    if (a.from != b.from) return a.from < b.from;
    if (a.to != b.to) return a.to < b.to;
    return a.type < b.type;
  });
  return p;
}

std::string node_label(const PictureNode& n) { return n.name + "\n(" + n.type + ")"; }

}  // namespace quiver::agents::inline view::render
