// The AGM world's schema: its symbol and edge types, the world file, and finding its nodes.
#include "quiver/agents/apps/agm/agm_schema.h"

#include <algorithm>
#include <deque>
#include <map>
#include <string>

namespace quiver::agents::inline apps::agm {

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

namespace {

std::string string_attr(const graph::Graph& g, NodeId n, const char* name) {
  if (const graph::Value* v = g.attr(n, name))
    if (const auto* s = v->get_if<std::string>()) return *s;
  return {};
}

// A node by its AGM id, or failing that by its name (as the planner prints steps).
NodeId node_by_key(const graph::Graph& g, const std::string& key) {
  for (NodeId n : g.nodes())
    if (string_attr(g, n, "agm_id") == key) return n;
  return node_id(g, key);
}

}  // namespace

RobotNames RobotNames::of(std::string_view tag) {
  RobotNames n;
  if (tag.empty()) return n;
  n.robot += tag;
  n.gripper += tag;
  n.plan += tag;
  return n;
}

std::optional<PlanStep> next_plan_step(const graph::Graph& g, std::string_view plan_node) {
  const NodeId plan = node_id(g, plan_node);
  if (plan.is_null() || string_attr(g, plan, "status") != "executing") return std::nullopt;
  PlanStep step;
  if (const graph::Value* v = g.attr(plan, "next"))
    if (const auto* i = v->get_if<std::int64_t>()) step.index = *i;
  if (const graph::Value* v = g.attr(plan, "version"))
    if (const auto* i = v->get_if<std::int64_t>()) step.version = *i;
  const std::string steps = string_attr(g, plan, "steps");
  std::size_t start = 0;
  std::string line;
  for (std::int64_t k = 0; start < steps.size(); ++k) {
    std::size_t end = steps.find('\n', start);
    if (end == std::string::npos) end = steps.size();
    if (k == step.index) {
      line = steps.substr(start, end - start);
      break;
    }
    start = end + 1;
  }
  // rule@{'var': 'node', ...}
  const std::size_t at = line.find("@{");
  if (at == std::string::npos) return std::nullopt;
  step.rule = line.substr(0, at);
  std::vector<std::string> quoted;
  for (std::size_t i = at + 2; i < line.size();) {
    const std::size_t a = line.find('\'', i);
    if (a == std::string::npos) break;
    const std::size_t b = line.find('\'', a + 1);
    if (b == std::string::npos) return std::nullopt;
    quoted.push_back(line.substr(a + 1, b - a - 1));
    i = b + 1;
  }
  if (quoted.size() % 2 != 0) return std::nullopt;
  for (std::size_t i = 0; i < quoted.size(); i += 2) {
    const NodeId n = node_by_key(g, quoted[i + 1]);
    if (n.is_null()) return std::nullopt;
    step.binding[quoted[i]] = n;
  }
  return step;
}

std::optional<std::array<double, 3>> world_position(const graph::Graph& g, NodeId n) {
  std::array<double, 3> p{0, 0, 0};
  bool hangs = false;
  for (int depth = 0; depth < 64; ++depth) {
    auto e = g.rt_edge(n);
    if (!e) break;
    hangs = true;
    // p in the parent's frame: R_PC p + t_PC (unit quaternion w, x, y, z).
    const auto& q = e->pose.rotation;
    const double w = q[0], x = q[1], y = q[2], z = q[3];
    const std::array<double, 3> v = p;
    const std::array<double, 3> r = {
        (1 - 2 * (y * y + z * z)) * v[0] + 2 * (x * y - w * z) * v[1] + 2 * (x * z + w * y) * v[2],
        2 * (x * y + w * z) * v[0] + (1 - 2 * (x * x + z * z)) * v[1] + 2 * (y * z - w * x) * v[2],
        2 * (x * z - w * y) * v[0] + 2 * (y * z + w * x) * v[1] + (1 - 2 * (x * x + y * y)) * v[2]};
    for (int i = 0; i < 3; ++i) p[i] = r[i] + e->pose.translation[i];
    n = e->parent;
  }
  if (!hangs) return std::nullopt;
  return p;
}

}  // namespace quiver::agents::inline apps::agm
