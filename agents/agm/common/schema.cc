#include "quiver/agents/agm/schema.h"

#include <algorithm>
#include <deque>
#include <map>
#include <string>

namespace quiver::agents::agm {

using graph::NodeId;

std::string_view role_grammar(std::string_view role) {
  std::string name(role);
  name += ".aggl";
  return embedded_file(name);
}

NodeId node_id(const graph::Graph& g, std::string_view name) {
  auto id = g.find_node(name);
  return id ? *id : NodeId{};
}

bool Polygon::contains(double x, double y) const {
  bool inside = false;
  const std::size_t n = points.size();
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
    const auto& a = points[i];
    const auto& b = points[j];
    // Half-open in y (a vertex is counted once); a crossing at exactly x counts as right of x.
    if ((a[1] > y) != (b[1] > y)) {
      const double cross_x = a[0] + (y - a[1]) * (b[0] - a[0]) / (b[1] - a[1]);
      if (x < cross_x) inside = !inside;
    }
  }
  return inside;
}

Result<Polygon> room_limits(const graph::Graph& g, NodeId room) {
  const graph::Value* v = g.attr(room, attr::kLimits);
  if (!v)
    return make_error(ErrorCode::kNotFound,
                      "room_limits(): room '" + g.name_of(room) + "' has no limits");
  const auto* xy = v->get_if<graph::DoubleVec>();
  if (!xy || xy->size() < 6 || xy->size() % 2 != 0)
    return make_error(ErrorCode::kInvalidArgument,
                      "room_limits(): room '" + g.name_of(room) +
                          "': limits must be a double_vec of 3 or more x, y pairs");
  Polygon p;
  for (std::size_t i = 0; i < xy->size(); i += 2) p.points.push_back({(*xy)[i], (*xy)[i + 1]});
  return p;
}

std::optional<NodeId> room_of(const graph::Graph& g, NodeId who) {
  std::optional<NodeId> best;
  const graph::Symbol room_type("room");
  for (const graph::EdgeKey& e : g.edges_from(who, edge::kIn))
    if (g.type_of(e.to) == room_type && (!best || e.to < *best)) best = e.to;
  return best;
}

std::optional<NodeId> room_at(const graph::Graph& g, double x, double y) {
  for (NodeId room : g.nodes_of_type("room")) {
    auto limits = room_limits(g, room);
    if (limits.ok() && limits->contains(x, y)) return room;
  }
  return std::nullopt;
}

std::vector<NodeId> room_path(const graph::Graph& g, NodeId from, NodeId to) {
  std::map<NodeId, NodeId> came_from{{from, from}};
  std::deque<NodeId> queue{from};
  while (!queue.empty()) {
    NodeId at = queue.front();
    queue.pop_front();
    if (at == to) break;
    auto next = g.edges_from(at, edge::kTransitable);
    std::sort(next.begin(), next.end(), [](const auto& a, const auto& b) { return a.to < b.to; });
    for (const graph::EdgeKey& e : next)
      if (came_from.emplace(e.to, at).second) queue.push_back(e.to);
  }
  if (!came_from.count(to)) return {};
  std::vector<NodeId> path{to};
  while (path.back() != from) path.push_back(came_from[path.back()]);
  std::reverse(path.begin(), path.end());
  return path;
}

}  // namespace quiver::agents::agm
