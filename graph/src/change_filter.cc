// A subscription's filter of change batches: the node and edge changes whose types or attributes it lists.
#include <algorithm>

#include "quiver/graph/graph.h"

namespace quiver::graph {
namespace {
bool any_of_names(const std::vector<std::string>& names, Symbol s) {
  if (s.is_null()) return false;
  const std::string& t = s.str();
  return std::find(names.begin(), names.end(), t) != names.end();
}
bool any_attr(const std::vector<std::string>& names, const std::vector<Symbol>& attrs) {
  return std::any_of(attrs.begin(), attrs.end(), [&](Symbol a) { return any_of_names(names, a); });
}
}  // namespace

ChangeBatch ChangeFilter::select(const ChangeBatch& b) const {
  if (empty()) return b;
  ChangeBatch out;
  out.local = b.local;
  out.origin = b.origin;
  out.origin_name = b.origin_name;
  for (const auto& n : b.nodes)
    if (any_of_names(node_types, n.type) || any_attr(attributes, n.attrs)) out.nodes.push_back(n);
  for (const auto& e : b.edges)
    if (any_of_names(edge_types, e.key.type) || any_attr(attributes, e.attrs)) out.edges.push_back(e);
  return out;
}

}  // namespace quiver::graph
