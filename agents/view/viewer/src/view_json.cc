// The world model as the viewer's page sees it: JSON for nodes, edges, poses, snapshots and the changes pushed to
// the page.
#include "quiver/agents/view/viewer/view_json.h"

#include "quiver/agents/view/images/image_attrs.h"
#include "quiver/agents/view/render/geometric_part.h"
#include "quiver/agents/view/render/type_colour.h"
#include "quiver/graph/world_file.h"
#include "quiver/kinematics/shape.h"

namespace quiver::agents::inline view::viewer {
namespace {

using nlohmann::json;

std::string writer_name(const Decor& d, const graph::ReplicaId& r) { return d.name_of ? d.name_of(r) : r.to_string(); }

json value_json(const graph::Value& v) {
  if (const auto* b = v.get_if<graph::Bytes>()) return json{{"bytes", b->size()}};
  return json::parse(graph::value_to_json_text(v), nullptr, false);
}

json attrs_json(const std::vector<graph::Symbol>& names,
                const std::function<std::vector<graph::AttrValue>(graph::Symbol)>& values_of, const Decor& d) {
  json out = json::array();
  for (graph::Symbol a : names) {
    if (a.str().rfind("__", 0) == 0) continue;  // internal registers (locks) are shown as such
    json values = json::array();
    auto vs = values_of(a);
    for (const graph::AttrValue& v : vs)
      values.push_back({{"v", value_json(v.value)}, {"writer", writer_name(d, v.dot.replica)}});
    out.push_back({{"name", a.str()}, {"type", vs.empty() ? "" : graph::to_string(vs[0].value.type())}, {"values", values}});
  }
  return out;
}

// The images a node holds (the images schema, docs/images.md): [{"prefix", "version"}] for the
// prefixes whose attributes check out.
json images_json(const graph::Graph& g, graph::NodeId id) {
  json out = json::array();
  for (graph::Symbol a : g.attr_names(id)) {
    const std::string& n = a.str();
    const std::string_view suffix = images::kEncodingSuffix;
    if (n.size() <= suffix.size() || n.compare(n.size() - suffix.size(), suffix.size(), suffix) != 0) continue;
    const std::string prefix = n.substr(0, n.size() - suffix.size());
    if (!images::image_info(g, id, prefix).ok()) continue;
    // The version changes when the picture does (the dot of the bytes' winning write).
    out.push_back({{"prefix", prefix}, {"version", g.attr_values(id, graph::Symbol(prefix))[0].dot.to_string()}});
  }
  return out;
}

json shape_json(const graph::Graph& g, graph::NodeId id) {
  auto s = kinematics::read_shape(g, id);
  if (!s.ok() || !s->has_value()) return nullptr;
  const kinematics::ShapeSpec& sp = **s;
  json j{{"kind", kinematics::to_string(sp.kind)}};
  switch (sp.kind) {
    case kinematics::ShapeSpec::Kind::kBox: j["size"] = {sp.size.x(), sp.size.y(), sp.size.z()}; break;
    case kinematics::ShapeSpec::Kind::kSphere: j["radius"] = sp.radius; break;
    case kinematics::ShapeSpec::Kind::kCylinder:
    case kinematics::ShapeSpec::Kind::kCapsule:
      j["radius"] = sp.radius;
      j["length"] = sp.length;
      break;
    case kinematics::ShapeSpec::Kind::kMesh:
      j["mesh"] = sp.mesh;
      j["scale"] = {sp.scale.x(), sp.scale.y(), sp.scale.z()};
      break;
  }
  return j;
}

bool symbolic(const graph::EdgeKey& k) { return !render::is_geometric(k); }

bool geometric(const graph::Graph& g, graph::NodeId id) { return render::is_geometric(g, id); }

std::string type_colour(const std::string& type) { return render::css_hex(render::type_colour(type)); }

json edge_ref(const graph::EdgeKey& k) {
  return {{"from", node_key(k.from)}, {"to", node_key(k.to)}, {"type", k.type.str()}};
}

}  // namespace

std::string node_key(graph::NodeId id) { return id.to_string(); }

json pose_json(const graph::Graph& g, graph::NodeId child) {
  auto e = g.rt_edge(child);
  if (!e) return nullptr;
  const auto& t = e->pose.translation;
  const auto& q = e->pose.rotation;
  return {{"id", node_key(child)}, {"parent", node_key(e->parent)}, {"t", {t[0], t[1], t[2]}},
          {"q", {q[0], q[1], q[2], q[3]}}, {"stamp", e->stamp}};
}

json node_json(const graph::Graph& g, graph::NodeId id, const Decor& d) {
  const std::string type = g.type_of(id).str();
  json j{{"id", node_key(id)},
         {"name", g.name_of(id)},
         {"type", type},
         {"colour", type_colour(type)},
         {"geometric", geometric(g, id)},
         {"pose", pose_json(g, id)},
         {"shape", shape_json(g, id)},
         {"images", images_json(g, id)},
         {"attrs", attrs_json(g.attr_names(id), [&](graph::Symbol a) { return g.attr_values(id, a); }, d)}};
  auto lock = d.locks.find(id);
  j["lock"] = lock == d.locks.end() ? json(nullptr)
                                    : json{{"holder", lock->second.holder},
                                           {"epoch", lock->second.epoch},
                                           {"priority", lock->second.priority}};
  json violated = json::array();
  for (const auto& [constraint, binding] : d.violations)
    for (const auto& [var, n] : binding)
      if (n == id) violated.push_back(constraint);
  j["violations"] = violated;
  return j;
}

json edge_json(const graph::Graph& g, const graph::EdgeKey& k, const Decor& d) {
  json j = edge_ref(k);
  j["colour"] = type_colour(k.type.str());
  j["attrs"] = attrs_json(g.edge_attr_names(k), [&](graph::Symbol a) { return g.edge_attr_values(k, a); }, d);
  return j;
}

json violations_json(const Decor& d) {
  json out = json::array();
  for (const auto& [constraint, binding] : d.violations) {
    json b = json::object();
    for (const auto& [var, n] : binding) b[var] = node_key(n);
    out.push_back({{"constraint", constraint}, {"binding", b}});
  }
  return out;
}

json snapshot_json(const graph::Graph& g, const Decor& d) {
  json nodes = json::array(), edges = json::array(), types = json::object();
  for (graph::NodeId id : g.nodes()) {
    nodes.push_back(node_json(g, id, d));
    types[g.type_of(id).str()] = type_colour(g.type_of(id).str());
    for (const graph::EdgeKey& k : g.edges_from(id))
      if (symbolic(k)) {
        edges.push_back(edge_json(g, k, d));
        types[k.type.str()] = type_colour(k.type.str());
      }
  }
  return {{"nodes", nodes}, {"edges", edges}, {"violations", violations_json(d)}, {"types", types}};
}

void ChangeAccumulator::add(const graph::ChangeBatch& b) {
  for (const graph::NodeChange& c : b.nodes) {
    if (c.kind == graph::ChangeKind::kDeleted) {
      gone_nodes_.insert(c.id);
      nodes_.erase(c.id);
      poses_.erase(c.id);
    } else {
      gone_nodes_.erase(c.id);
      nodes_.insert(c.id);
    }
  }
  for (const graph::EdgeChange& c : b.edges) {
    if (!symbolic(c.key)) {
      // A pose sample moves the child; a new or lost RT parent changes the child's node.
      if (c.kind == graph::ChangeKind::kUpdated) poses_.insert(c.key.to);
      else nodes_.insert(c.key.to);
      continue;
    }
    nodes_.insert(c.key.from);  // "geometric" depends on the symbolic edges a node has
    nodes_.insert(c.key.to);
    if (c.kind == graph::ChangeKind::kDeleted) {
      gone_edges_.insert(c.key);
      edges_.erase(c.key);
    } else {
      gone_edges_.erase(c.key);
      edges_.insert(c.key);
    }
  }
}

json ChangeAccumulator::drain(const graph::Graph& g, const Decor& d) {
  json nodes = json::array(), gone_nodes = json::array(), edges = json::array(), gone_edges = json::array(),
       poses = json::array();
  for (graph::NodeId id : nodes_) {
    if (g.has_node(id)) nodes.push_back(node_json(g, id, d));
    else gone_nodes.push_back(node_key(id));
  }
  for (graph::NodeId id : gone_nodes_) gone_nodes.push_back(node_key(id));
  for (graph::NodeId id : poses_)
    if (!nodes_.contains(id) && g.has_node(id)) {
      json p = pose_json(g, id);
      if (!p.is_null()) poses.push_back(std::move(p));
    }
  for (const graph::EdgeKey& k : edges_) {
    if (g.has_edge(k.from, k.to, k.type)) edges.push_back(edge_json(g, k, d));
    else gone_edges.push_back(edge_ref(k));
  }
  for (const graph::EdgeKey& k : gone_edges_) gone_edges.push_back(edge_ref(k));
  nodes_.clear();
  gone_nodes_.clear();
  poses_.clear();
  edges_.clear();
  gone_edges_.clear();
  return {{"nodes", nodes}, {"deleted_nodes", gone_nodes}, {"edges", edges}, {"deleted_edges", gone_edges},
          {"poses", poses}};
}

json summary_json(const graph::Graph& g, const graph::ChangeBatch& b) {
  auto name = [&](graph::NodeId id) {
    std::string n = g.name_of(id);
    return n.empty() ? id.to_string() : n;
  };
  json created = json::array(), deleted = json::array(), updated = json::array(), ec = json::array(),
       ed = json::array(), changed = json::array(), changed_edges = json::array();
  int poses = 0;
  for (const graph::NodeChange& c : b.nodes) {
    changed.push_back(node_key(c.id));
    if (c.kind == graph::ChangeKind::kCreated) created.push_back(name(c.id) + " (" + c.type.str() + ")");
    else if (c.kind == graph::ChangeKind::kDeleted) deleted.push_back(name(c.id) + " (" + c.type.str() + ")");
    else {
      std::string attrs;
      for (graph::Symbol a : c.attrs) attrs += (attrs.empty() ? "" : ", ") + a.str();
      updated.push_back(name(c.id) + ": " + (c.renamed ? "renamed" : attrs));
    }
  }
  for (const graph::EdgeChange& c : b.edges) {
    const std::string text = name(c.key.from) + " -[" + c.key.type.str() + "]-> " + name(c.key.to);
    if (!symbolic(c.key) && c.kind == graph::ChangeKind::kUpdated) {
      ++poses;
      changed.push_back(node_key(c.key.to));
      continue;
    }
    if (symbolic(c.key)) changed_edges.push_back(edge_ref(c.key));
    if (!symbolic(c.key)) {
      changed.push_back(node_key(c.key.to));  // a move
    } else if (c.kind == graph::ChangeKind::kDeleted) {
      ed.push_back(text);
    } else if (c.kind == graph::ChangeKind::kCreated) {
      ec.push_back(text);
    } else {
      std::string attrs;
      for (graph::Symbol a : c.attrs) attrs += (attrs.empty() ? "" : ", ") + a.str();
      updated.push_back(text + ": " + attrs);
    }
  }
  return {{"created", created}, {"deleted", deleted},       {"updated", updated}, {"edges_created", ec},
          {"edges_deleted", ed}, {"poses", poses}, {"changed", changed}, {"changed_edges", changed_edges}};
}

}  // namespace quiver::agents::inline view::viewer
