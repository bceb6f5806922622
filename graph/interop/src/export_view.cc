// The visible graph as both exporters walk it: nodes with their file ids, attributes split between the node and
// its RT link, RT parents with their poses, symbolic edges, in one deterministic order.
#include "export_view.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>
#include <unordered_set>

#include "euler_xyz.h"
#include "plan.h"
#include "text_values.h"

namespace quiver::interop::internal {

using graph::NodeId;
using graph::Symbol;

ExportView make_export_view(const graph::Graph& g, const IdPolicy& policy, double metres_per_unit) {
  ExportView view;
  std::vector<NodeId> ids = g.nodes();
  std::vector<ExportNode>& nodes = view.nodes;
  nodes.reserve(ids.size());
  const Symbol id_attr = Symbol::find(policy.attr);

  // Ids: a usable, unique id attribute is kept; the rest get fresh numbers.
  std::unordered_set<std::string> used;
  std::uint64_t largest = 0;
  bool any_numeric = false;
  std::vector<std::size_t> fresh;
  for (NodeId id : ids) {
    ExportNode n;
    n.id = id;
    n.name = g.name_of(id);
    n.type = g.type_of(id).str();
    if (const graph::Value* v = id_attr.is_null() ? nullptr : g.attr(id, id_attr)) {
      if (auto text = policy.id_of(*v)) {
        if (used.insert(*text).second) {
          n.file_id = *text;
          n.own_id = true;
        } else {
          view.warnings.push_back("node " + in_quotes(n.name) + ": its " + policy.what + " " + *text +
                                  " is taken by another node: given a new one");
        }
      } else {
        view.warnings.push_back("node " + in_quotes(n.name) + ": its " + policy.attr + " (" + v->to_string() +
                                ") is not a usable " + policy.what + ": given a new one");
      }
    }
    if (n.own_id) {
      std::uint64_t number;
      if (parse_uint64(n.file_id, number)) {
        largest = std::max(largest, number);
        any_numeric = true;
      }
    } else {
      fresh.push_back(nodes.size());
    }
    nodes.push_back(std::move(n));
  }
  std::sort(fresh.begin(), fresh.end(), [&](std::size_t a, std::size_t b) { return nodes[a].name < nodes[b].name; });
  std::uint64_t next = any_numeric ? largest + 1 : 1;
  for (std::size_t i : fresh) {
    while (used.count(std::to_string(next))) ++next;
    nodes[i].file_id = std::to_string(next++);
    used.insert(nodes[i].file_id);
  }
  std::sort(nodes.begin(), nodes.end(), [](const ExportNode& a, const ExportNode& b) {
    std::uint64_t x, y;
    const bool nx = parse_uint64(a.file_id, x), ny = parse_uint64(b.file_id, y);
    if (nx != ny) return nx;
    if (nx) return x < y;
    return a.file_id < b.file_id;
  });
  std::unordered_map<NodeId, std::size_t> index;
  for (std::size_t i = 0; i < nodes.size(); ++i) index.emplace(nodes[i].id, i);

  // Attributes, RT parents and poses.
  std::unordered_set<std::string> consumed(policy.consumed.begin(), policy.consumed.end());
  consumed.insert(policy.attr);
  for (ExportNode& n : nodes) {
    if (auto rt = g.rt_edge(n.id)) {
      n.parent = index.at(rt->parent);
      n.pose = rt->pose;
      xyz_from_pose(n.pose, metres_per_unit, n.t, n.r);
      bool finite = true;
      for (int i = 0; i < 3; ++i) finite = finite && std::isfinite(n.t[i]) && std::isfinite(n.r[i]);
      if (!finite) {
        view.warnings.push_back("node " + in_quotes(n.name) + ": its RT pose is not finite in the file's unit: written as 0");
        n.t = n.r = {0, 0, 0};
      }
    }
    for (Symbol a : g.attr_names(n.id)) {
      const std::string& name = a.str();
      const graph::Value* v = g.attr(n.id, a);
      if (consumed.count(name)) continue;
      if (n.parent && name.size() > kRtAttrPrefix.size() && name.compare(0, kRtAttrPrefix.size(), kRtAttrPrefix) == 0)
        n.rt_attrs.emplace_back(name.substr(kRtAttrPrefix.size()), v);
      else
        n.attrs.emplace_back(name, v);
    }
    auto by_name = [](const auto& a, const auto& b) { return a.first < b.first; };
    std::sort(n.attrs.begin(), n.attrs.end(), by_name);
    std::sort(n.rt_attrs.begin(), n.rt_attrs.end(), by_name);
  }
  for (ExportNode& n : nodes) {
    int depth = 0;
    for (auto p = n.parent; p && depth <= static_cast<int>(nodes.size()); p = nodes[*p].parent) ++depth;
    n.depth = depth;
  }

  // Symbolic edges, by source, then target, then type.
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    std::vector<ExportEdge> out;
    for (const graph::EdgeKey& k : g.edges_from(nodes[i].id)) {
      if (k.type == graph::symbols::rt()) continue;
      ExportEdge e;
      e.from = i;
      e.to = index.at(k.to);
      e.type = k.type.str();
      for (Symbol a : g.edge_attr_names(k)) e.attrs.emplace_back(a.str(), g.edge_attr(k, a));
      std::sort(e.attrs.begin(), e.attrs.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
      out.push_back(std::move(e));
    }
    std::sort(out.begin(), out.end(), [](const ExportEdge& a, const ExportEdge& b) {
      return a.to != b.to ? a.to < b.to : a.type < b.type;
    });
    for (ExportEdge& e : out) {
      nodes[i].edges.push_back(view.edges.size());
      view.edges.push_back(std::move(e));
    }
  }
  return view;
}

}  // namespace quiver::interop::internal
