#pragma once
// Whether two graphs hold the same visible world: the same node names with the same types and
// attribute values, the same edges (by names and type) with the same attributes, the same RT
// parents, and poses equal to a tolerance (translations in metres, relative beyond 1 m;
// rotations compared as matrices, so q and -q are one rotation). Used by the interop tests and the fuzz targets.

#include <array>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "quiver/graph/graph.h"

namespace quiver::interop::testing {

inline std::array<double, 9> rotation_matrix(const graph::Pose& X) {
  const double w = X.rotation[0], x = X.rotation[1], y = X.rotation[2], z = X.rotation[3];
  return {1 - 2 * (y * y + z * z), 2 * (x * y - w * z),     2 * (x * z + w * y),
          2 * (x * y + w * z),     1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
          2 * (x * z - w * y),     2 * (y * z + w * x),     1 - 2 * (x * x + y * y)};
}

/// One line per difference; empty when the worlds are the same.
inline std::vector<std::string> world_differences(const graph::Graph& a, const graph::Graph& b, double tol = 1e-12) {
  std::vector<std::string> out;
  using Attrs = std::map<std::string, graph::Value>;
  struct Node {
    std::string type;
    Attrs attrs;
    std::string parent;
    graph::Pose pose;
  };
  auto nodes_of = [](const graph::Graph& g) {
    std::map<std::string, Node> m;
    for (graph::NodeId id : g.nodes()) {
      Node n;
      n.type = g.type_of(id).str();
      for (graph::Symbol s : g.attr_names(id)) n.attrs.emplace(s.str(), *g.attr(id, s));
      if (auto rt = g.rt_edge(id)) {
        n.parent = g.name_of(rt->parent);
        n.pose = rt->pose;
      }
      m.emplace(g.name_of(id), std::move(n));
    }
    return m;
  };
  auto edges_of = [](const graph::Graph& g) {
    std::map<std::string, Attrs> m;
    for (graph::NodeId id : g.nodes())
      for (const graph::EdgeKey& k : g.edges_from(id)) {
        if (k.type == graph::symbols::rt()) continue;
        Attrs attrs;
        for (graph::Symbol s : g.edge_attr_names(k)) attrs.emplace(s.str(), *g.edge_attr(k, s));
        m.emplace(g.name_of(k.from) + " -> " + g.name_of(k.to) + " (" + k.type.str() + ")", std::move(attrs));
      }
    return m;
  };
  const auto na = nodes_of(a), nb = nodes_of(b);
  for (const auto& [name, n] : na) {
    auto it = nb.find(name);
    if (it == nb.end()) {
      out.push_back("node '" + name + "' only in the first");
      continue;
    }
    const Node& m = it->second;
    if (n.type != m.type) out.push_back("node '" + name + "': type " + n.type + " vs " + m.type);
    for (const auto& [k, v] : n.attrs) {
      auto w = m.attrs.find(k);
      if (w == m.attrs.end()) out.push_back("node '" + name + "': attribute " + k + " only in the first");
      else if (!(v == w->second))
        out.push_back("node '" + name + "': attribute " + k + ": " + v.to_string() + " (" + graph::to_string(v.type()) +
                      ") vs " + w->second.to_string() + " (" + graph::to_string(w->second.type()) + ")");
    }
    for (const auto& [k, v] : m.attrs)
      if (!n.attrs.count(k)) out.push_back("node '" + name + "': attribute " + k + " only in the second");
    if (n.parent != m.parent) out.push_back("node '" + name + "': RT parent '" + n.parent + "' vs '" + m.parent + "'");
    if (!n.parent.empty()) {
      double dt = 0, dr = 0;
      // Relative to the distance beyond 1 m: the formats' numbers carry 15 to 17 digits.
      for (int i = 0; i < 3; ++i)
        dt = std::max(dt, std::fabs(n.pose.translation[i] - m.pose.translation[i]) /
                              std::max(1.0, std::fabs(n.pose.translation[i])));
      const auto ra = rotation_matrix(n.pose), rb = rotation_matrix(m.pose);
      for (int i = 0; i < 9; ++i) dr = std::max(dr, std::fabs(ra[i] - rb[i]));
      if (!(dt <= tol) || !(dr <= tol))
        out.push_back("node '" + name + "': pose differs by " + std::to_string(dt) + " m, " + std::to_string(dr) +
                      " in the rotation matrix");
    }
  }
  for (const auto& [name, n] : nb)
    if (!na.count(name)) out.push_back("node '" + name + "' only in the second");
  const auto ea = edges_of(a), eb = edges_of(b);
  for (const auto& [key, attrs] : ea) {
    auto it = eb.find(key);
    if (it == eb.end()) {
      out.push_back("edge " + key + " only in the first");
      continue;
    }
    if (attrs.size() != it->second.size()) out.push_back("edge " + key + ": another set of attributes");
    for (const auto& [k, v] : attrs) {
      auto w = it->second.find(k);
      if (w == it->second.end() || !(v == w->second)) out.push_back("edge " + key + ": attribute " + k + " differs");
    }
  }
  for (const auto& [key, attrs] : eb)
    if (!ea.count(key)) out.push_back("edge " + key + " only in the second");
  return out;
}

}  // namespace quiver::interop::testing
