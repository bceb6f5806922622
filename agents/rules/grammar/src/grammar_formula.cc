// Formulas evaluated at a match, and the bindings of quantified variables enumerated, in the state a change
// starts from; shared by rules, constraints and effects.
#include "grammar_formula.h"

#include <algorithm>

namespace quiver::agents::inline rules::internal {

using graph::EdgeKey;
using graph::Graph;
using graph::NodeId;

bool compare(const graph::Value& v, CompareOp op, const graph::Value& lit) {
  auto as_double = [](const graph::Value& x, double& out) {
    switch (x.type()) {
      case graph::ValueType::kInt32:
        out = *x.get_if<std::int32_t>();
        return true;
      case graph::ValueType::kInt64:
        out = static_cast<double>(*x.get_if<std::int64_t>());
        return true;
      case graph::ValueType::kUInt32:
        out = *x.get_if<std::uint32_t>();
        return true;
      case graph::ValueType::kUInt64:
        out = static_cast<double>(*x.get_if<std::uint64_t>());
        return true;
      case graph::ValueType::kFloat:
        out = *x.get_if<float>();
        return true;
      case graph::ValueType::kDouble:
        out = *x.get_if<double>();
        return true;
      default:
        return false;
    }
  };
  double a, b;
  int cmp;
  if (as_double(v, a) && as_double(lit, b)) {
    cmp = a < b ? -1 : (a > b ? 1 : 0);
  } else if (v.type() == lit.type()) {
    if (const auto* s = v.get_if<std::string>()) {
      const auto& t = *lit.get_if<std::string>();
      cmp = *s < t ? -1 : (*s > t ? 1 : 0);
    } else {
      cmp = v == lit ? 0 : 1;
      if (op != CompareOp::kEq && op != CompareOp::kNe) return false;
    }
  } else {
    return op == CompareOp::kNe;
  }
  switch (op) {
    case CompareOp::kEq:
      return cmp == 0;
    case CompareOp::kNe:
      return cmp != 0;
    case CompareOp::kLt:
      return cmp < 0;
    case CompareOp::kLe:
      return cmp <= 0;
    case CompareOp::kGt:
      return cmp > 0;
    case CompareOp::kGe:
      return cmp >= 0;
  }
  return false;
}

std::vector<NodeId> candidates(const Graph& g, const TypeSystem& types, const std::string& var,
                               const std::string& type,
                               const std::vector<const PatternEdge*>& edges, const Binding& b) {
  std::vector<NodeId> out;
  bool anchored = false;
  for (const PatternEdge* e : edges) {
    if (e->negated) continue;
    auto from = b.find(e->from), to = b.find(e->to);
    if (e->to == var && e->from != var && from != b.end()) {
      for (const EdgeKey& k : g.edges_from(from->second, e->symbol)) out.push_back(k.to);
      anchored = true;
      break;
    }
    if (e->from == var && e->to != var && to != b.end()) {
      for (const EdgeKey& k : g.edges_to(to->second, e->symbol)) out.push_back(k.from);
      anchored = true;
      break;
    }
  }
  if (!anchored) {
    // Unanchored: every node of the type (documented cost).
    for (const std::string& t : types.subtypes(type))
      for (NodeId n : g.nodes_of_type(graph::Symbol::find(t))) out.push_back(n);
    return out;
  }
  std::vector<NodeId> typed;
  for (NodeId n : out)
    if (types.is_a(g.type_of(n).str(), type)) typed.push_back(n);
  return typed;
}

void collect_edges(const Formula& f, std::vector<const PatternEdge*>& out) {
  if (f.kind == Formula::Kind::kEdge) out.push_back(&f.edge);
  if (f.kind == Formula::Kind::kAnd)
    for (const auto& k : f.kids) collect_edges(k, out);
}

namespace {

bool enumerate_from(const Graph& g, const TypeSystem& types, const std::vector<PatternNode>& vars,
                    std::size_t i, bool distinct, const Formula& guard,
                    const std::vector<const PatternEdge*>& edges, Binding& b,
                    const std::function<bool(Binding&)>& each) {
  if (i == vars.size()) {
    if (!eval(g, types, guard, b)) return true;
    return each(b);
  }
  const std::string& var = vars[i].var;
  // A quantified variable may shadow one of the rule's: hide the outer value while binding it.
  std::optional<NodeId> outer;
  if (auto it = b.find(var); it != b.end()) {
    outer = it->second;
    b.erase(it);
  }
  bool go_on = true;
  for (NodeId n : candidates(g, types, var, vars[i].type, edges, b)) {
    if (distinct) {
      bool used = false;
      for (const auto& [v, m] : b) used = used || m == n;
      if (used) continue;
    }
    b[var] = n;
    go_on = enumerate_from(g, types, vars, i + 1, distinct, guard, edges, b, each);
    b.erase(var);
    if (!go_on) break;
  }
  if (outer) b[var] = *outer;
  return go_on;
}

}  // namespace

bool enumerate(const Graph& g, const TypeSystem& types, const std::vector<PatternNode>& vars,
               bool distinct, const Formula& guard, const std::vector<const PatternEdge*>& edges,
               Binding& b, const std::function<bool(Binding&)>& each) {
  return enumerate_from(g, types, vars, 0, distinct, guard, edges, b, each);
}

bool eval(const Graph& g, const TypeSystem& types, const Formula& f, Binding& b) {
  switch (f.kind) {
    case Formula::Kind::kTrue:
      return true;
    case Formula::Kind::kFalse:
      return false;
    case Formula::Kind::kAnd:
      for (const auto& k : f.kids)
        if (!eval(g, types, k, b)) return false;
      return true;
    case Formula::Kind::kOr:
      for (const auto& k : f.kids)
        if (eval(g, types, k, b)) return true;
      return false;
    case Formula::Kind::kNot:
      return !eval(g, types, f.kids[0], b);
    case Formula::Kind::kEdge:
      return g.has_edge(b.at(f.edge.from), b.at(f.edge.to), f.edge.symbol);
    case Formula::Kind::kSame:
      return b.at(f.edge.from) == b.at(f.edge.to);
    case Formula::Kind::kHas:
      return g.attr(b.at(f.var), f.attr_symbol) != nullptr;
    case Formula::Kind::kCompare: {
      const graph::Value* v =
          f.var.empty() ? g.edge_attr(EdgeKey{b.at(f.edge.from), b.at(f.edge.to), f.edge.symbol},
                                      f.attr_symbol)
                        : g.attr(b.at(f.var), f.attr_symbol);
      return v != nullptr && compare(*v, f.op, f.literal);
    }
    case Formula::Kind::kExists: {
      std::vector<const PatternEdge*> edges;
      collect_edges(f.kids[0], edges);
      bool found = false;
      enumerate(g, types, f.vars, f.distinct, f.kids[0], edges, b, [&](Binding&) {
        found = true;
        return false;
      });
      return found;
    }
    case Formula::Kind::kForall: {
      std::vector<const PatternEdge*> edges;
      collect_edges(f.kids[0], edges);
      bool all = true;
      enumerate(g, types, f.vars, f.distinct, f.kids[0], edges, b, [&](Binding& inner) {
        all = eval(g, types, f.kids[1], inner);
        return all;
      });
      return all;
    }
  }
  return false;
}

Guard guard_of(const Pattern& p) {
  Guard g;
  Formula& f = g.formula;
  f.kind = Formula::Kind::kAnd;
  for (const auto& e : p.edges) {
    Formula atom;
    atom.kind = Formula::Kind::kEdge;
    atom.edge = e;
    atom.edge.negated = false;
    if (e.negated) {
      Formula neg;
      neg.kind = Formula::Kind::kNot;
      neg.kids.push_back(atom);
      f.kids.push_back(neg);
    } else {
      f.kids.push_back(atom);
      g.edges.push_back(
          &e);  // what collect_edges(f) finds, but pointing into `p` (which stays put)
    }
  }
  return g;
}

}  // namespace quiver::agents::inline rules::internal
