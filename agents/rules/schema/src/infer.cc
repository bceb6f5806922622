// A starting schema inferred from a world: its node types, its edge types with the node types at
// their ends, its attributes with their value types.
#include "quiver/agents/rules/schema/infer.h"

#include <algorithm>

namespace quiver::agents::inline rules::schema {
namespace {

void add_unique(std::vector<std::string>& v, const std::string& s) {
  if (std::find(v.begin(), v.end(), s) == v.end()) {
    v.push_back(s);
    std::sort(v.begin(), v.end());
  }
}

void widen(Schema& s, std::string_view attr, graph::ValueType t) {
  const auto declared = Schema::declared_name(attr);
  if (!declared) return;  // the runtime's own
  const std::string& name = *declared;
  auto it = s.attributes().find(name);
  if (it == s.attributes().end()) {
    AttributeSpec a;
    a.type = t;
    s.declare_attribute(name, a);
  } else if (it->second.type && *it->second.type != t) {
    AttributeSpec a = it->second;
    a.type.reset();
    s.declare_attribute(name, a);
  }
}

void add_edge(Schema& s, const std::string& type, const std::string& from, const std::string& to) {
  auto it = s.edge_types().find(type);
  EdgeTypeSpec e = it == s.edge_types().end() ? EdgeTypeSpec{} : it->second;
  add_unique(e.from, from);
  add_unique(e.to, to);
  s.declare_edge_type(type, e);
}

}  // namespace

void infer_from_graph(const graph::Graph& g, Schema& s) {
  for (graph::NodeId n : g.nodes()) {
    const std::string type = g.type_of(n).str();
    if (!s.has_node_type(type)) s.declare_node_type(type);
    for (graph::Symbol a : g.attr_names(n))
      if (const graph::Value* v = g.attr(n, a)) widen(s, a.str(), v->type());
  }
  for (graph::NodeId n : g.nodes())
    for (const graph::EdgeKey& e : g.edges_from(n)) {
      add_edge(s, e.type.str(), g.type_of(e.from).str(), g.type_of(e.to).str());
      if (e.type.str() == "RT") continue;  // its attributes are the child's rt: ones, seen above
      for (graph::Symbol a : g.edge_attr_names(e))
        if (const graph::Value* v = g.edge_attr(e, a)) widen(s, a.str(), v->type());
    }
}

}  // namespace quiver::agents::inline rules::schema
