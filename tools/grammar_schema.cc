// A grammar against the shared vocabulary: undeclared node types and edge labels, edges joining
// types the schema does not let them join; and the vocabulary a grammar implies.
#include "grammar_schema.h"

#include <algorithm>
#include <functional>

namespace quiver::tools {
namespace {

using agents::Pattern;

// Calls f(pattern, where) for every pattern of the grammar: rules' sides, their foralls, and
// constraints.
void each_pattern(const agents::Grammar& g, const std::function<void(const Pattern&, const std::string&)>& f) {
  for (const agents::Rule& r : g.rules) {
    const std::string where = "rule '" + r.name + "' (" + r.file + ":" + std::to_string(r.loc.line) + ")";
    f(r.lhs, where);
    f(r.rhs, where);
    for (const auto& fa : r.foralls) {
      f(fa.lhs, where);
      f(fa.rhs, where);
    }
  }
  for (const agents::Constraint& c : g.constraints)
    f(c.forbid, "constraint '" + c.name + "' (line " + std::to_string(c.loc.line) + ")");
}

// A pattern variable's type can meet an allowed end type: one is the other or inherits from it.
bool meets(const agents::schema::Schema& s, const std::string& type, const std::vector<std::string>& allowed) {
  if (allowed.empty() || type.empty()) return true;
  return std::any_of(allowed.begin(), allowed.end(),
                     [&](const std::string& a) { return s.is_a(type, a) || s.is_a(a, type); });
}

void add_unique(std::vector<std::string>& v, const std::string& x) {
  if (!x.empty() && std::find(v.begin(), v.end(), x) == v.end()) {
    v.push_back(x);
    std::sort(v.begin(), v.end());
  }
}

}  // namespace

void pattern_schema_errors(const Pattern& p, const agents::schema::Schema& s, const std::string& where,
                           std::vector<std::string>& out) {
  auto once = [&](std::string line) {
    if (std::find(out.begin(), out.end(), line) == out.end()) out.push_back(std::move(line));
  };
  if (s.open()) return;
  for (const auto& n : p.nodes)
    if (!n.type.empty() && !s.has_node_type(n.type))
      once(where + ": the node type '" + n.type + "' (variable " + n.var + ") is not in the schema " + s.where());
  for (const auto& e : p.edges) {
    auto spec = s.edge_types().find(e.label);
    if (spec == s.edge_types().end()) {
      once(where + ": the edge type '" + e.label + "' (" + e.from + " -> " + e.to + ") is not in the schema " +
           s.where());
      continue;
    }
    const auto* from = p.node(e.from);
    const auto* to = p.node(e.to);
    if (from != nullptr && !meets(s, from->type, spec->second.from))
      once(where + ": an edge '" + e.label + "' starts at " + e.from + ", a '" + from->type +
           "', which the schema never lets it start at");
    if (to != nullptr && !meets(s, to->type, spec->second.to))
      once(where + ": an edge '" + e.label + "' ends at " + e.to + ", a '" + to->type +
           "', which the schema never lets it end at");
  }
}

std::vector<std::string> grammar_schema_errors(const agents::Grammar& g, const agents::schema::Schema& s) {
  std::vector<std::string> out;
  if (s.open()) return out;
  for (const std::string& t : g.types.names())
    if (!s.has_node_type(t)) out.push_back("types: the node type '" + t + "' is not in the schema " + s.where());
  each_pattern(g, [&](const Pattern& p, const std::string& where) { pattern_schema_errors(p, s, where, out); });
  return out;
}

void infer_from_grammar(const agents::Grammar& g, agents::schema::Schema& s) {
  for (const std::string& t : g.types.names()) s.declare_node_type(t, g.types.bases(t));
  each_pattern(g, [&](const Pattern& p, const std::string&) {
    for (const auto& n : p.nodes)
      if (!n.type.empty() && !s.has_node_type(n.type)) s.declare_node_type(n.type);
    for (const auto& e : p.edges) {
      auto it = s.edge_types().find(e.label);
      agents::schema::EdgeTypeSpec spec = it == s.edge_types().end() ? agents::schema::EdgeTypeSpec{} : it->second;
      if (const auto* n = p.node(e.from)) add_unique(spec.from, n->type);
      if (const auto* n = p.node(e.to)) add_unique(spec.to, n->type);
      s.declare_edge_type(e.label, spec);
    }
  });
}

}  // namespace quiver::tools
