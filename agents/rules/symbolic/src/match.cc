// Patterns and formulas compiled against a vocabulary into slots, then matched and evaluated on symbolic states.
#include "quiver/agents/rules/symbolic/match.h"

#include <algorithm>

namespace quiver::agents::inline rules::symbolic {
namespace {

using K = Formula::Kind;

// Positive edges of a formula's top-level conjunction (they anchor quantified variables).
void anchors(const CFormula& f, std::vector<const CEdge*>& out) {
  if (f.kind == K::kEdge && !f.edge.negated) out.push_back(&f.edge);
  if (f.kind == K::kAnd)
    for (const CFormula& k : f.kids) anchors(k, out);
}

// Candidates for slot `v` of type `t`: neighbours of a bound node along an anchor edge, else
// every alive node of the type. Sorted, unique.
void candidates(const State& s, const Vocabulary& voc, int v, TypeIx t,
                const std::vector<const CEdge*>& edges, const Binding& b,
                std::vector<NodeIx>& out) {
  out.clear();
  for (const CEdge* e : edges) {
    if (e->from == v && e->to != v && b[e->to] != kNoNode) {
      auto [lo, hi] = s.in(b[e->to], e->label);
      for (auto* p = lo; p != hi; ++p) out.push_back(p->to);
    } else if (e->to == v && e->from != v && b[e->from] != kNoNode) {
      auto [lo, hi] = s.out(b[e->from], e->label);
      for (auto* p = lo; p != hi; ++p) out.push_back(p->to);
    } else {
      continue;
    }
    std::erase_if(out, [&](NodeIx n) { return !voc.is_a(s.type(n), t); });
    return;
  }
  for (NodeIx n = 0; n < s.size(); ++n)
    if (s.alive(n) && voc.is_a(s.type(n), t)) out.push_back(n);
}

// Enumerates bindings of `vars[i..]`, calling `each` (which returns false to stop).
bool bind_vars(const State& s, const Vocabulary& voc, const std::vector<std::pair<int, TypeIx>>& vars,
               std::size_t i, bool distinct, const std::vector<const CEdge*>& edges, Binding& b,
               const std::vector<NodeIx>& outer, const std::function<bool()>& each) {
  if (i == vars.size()) return each();
  const auto [slot, type] = vars[i];
  std::vector<NodeIx> cand;
  candidates(s, voc, slot, type, edges, b, cand);
  for (NodeIx n : cand) {
    if (distinct) {
      if (std::find(outer.begin(), outer.end(), n) != outer.end()) continue;
      bool used = false;
      for (std::size_t j = 0; j < i; ++j) used = used || b[vars[j].first] == n;
      if (used) continue;
    }
    b[slot] = n;
    if (!bind_vars(s, voc, vars, i + 1, distinct, edges, b, outer, each)) {
      b[slot] = kNoNode;
      return false;
    }
  }
  b[slot] = kNoNode;
  return true;
}

bool quantified(const State& s, const Vocabulary& voc, const CFormula& f, Binding& b) {
  std::vector<NodeIx> saved;
  for (auto [slot, t] : f.vars) saved.push_back(b[slot]);
  for (auto [slot, t] : f.vars) b[slot] = kNoNode;
  std::vector<NodeIx> outer;
  if (f.distinct)
    for (NodeIx n : b)
      if (n != kNoNode) outer.push_back(n);
  std::vector<const CEdge*> edges;
  anchors(f.kids[0], edges);
  bool result;
  if (f.kind == K::kExists) {
    result = false;
    bind_vars(s, voc, f.vars, 0, f.distinct, edges, b, outer, [&] {
      result = eval(s, voc, f.kids[0], b);
      return !result;
    });
  } else {
    result = true;
    bind_vars(s, voc, f.vars, 0, f.distinct, edges, b, outer, [&] {
      if (eval(s, voc, f.kids[0], b) && !eval(s, voc, f.kids[1], b)) result = false;
      return result;
    });
  }
  for (std::size_t i = 0; i < f.vars.size(); ++i) b[f.vars[i].first] = saved[i];
  return result;
}

}  // namespace

bool compile(const Formula& f, Vocabulary& voc, Scope& scope, CFormula& out, std::string& why) {
  out.kind = f.kind;
  auto slot_of = [&](const std::string& v) {
    const int s = scope.find(v);
    if (s < 0 && why.empty()) why = "variable '" + v + "' is not bound here";
    return s;
  };
  switch (f.kind) {
    case K::kTrue:
    case K::kFalse:
      return true;
    case K::kAnd:
    case K::kOr:
    case K::kNot:
      for (const Formula& k : f.kids) {
        out.kids.emplace_back();
        if (!compile(k, voc, scope, out.kids.back(), why)) return false;
      }
      return true;
    case K::kEdge:
    case K::kSame:
      out.edge.from = slot_of(f.edge.from);
      out.edge.to = slot_of(f.edge.to);
      out.edge.negated = f.edge.negated;
      if (f.kind == K::kEdge) out.edge.label = voc.label(f.edge.label);
      return out.edge.from >= 0 && out.edge.to >= 0;
    case K::kExists:
    case K::kForall: {
      Scope inner = scope;
      out.distinct = f.distinct;
      for (const PatternNode& v : f.vars) out.vars.emplace_back(inner.add(v.var), voc.type(v.type));
      for (const Formula& k : f.kids) {
        out.kids.emplace_back();
        if (!compile(k, voc, inner, out.kids.back(), why)) return false;
      }
      if (f.kind == K::kForall && out.kids.size() == 1) out.kids.insert(out.kids.begin(), CFormula{});
      scope.slots = std::max(scope.slots, inner.slots);
      return true;
    }
    case K::kCompare:
    case K::kHas:
      why = "attribute '" + f.attr + "' cannot be read in a symbolic state (line " +
            std::to_string(f.loc.line) + ")";
      return false;
  }
  return false;
}

bool eval(const State& s, const Vocabulary& voc, const CFormula& f, Binding& b) {
  switch (f.kind) {
    case K::kTrue:
      return true;
    case K::kFalse:
      return false;
    case K::kAnd:
      for (const CFormula& k : f.kids)
        if (!eval(s, voc, k, b)) return false;
      return true;
    case K::kOr:
      for (const CFormula& k : f.kids)
        if (eval(s, voc, k, b)) return true;
      return false;
    case K::kNot:
      return !eval(s, voc, f.kids[0], b);
    case K::kEdge: {
      const NodeIx a = b[f.edge.from], c = b[f.edge.to];
      const bool has = a != kNoNode && c != kNoNode && s.has_edge(a, c, f.edge.label);
      return has != f.edge.negated;
    }
    case K::kSame:
      return b[f.edge.from] == b[f.edge.to];
    case K::kExists:
    case K::kForall:
      return quantified(s, voc, f, b);
    default:
      return false;
  }
}

CPattern compile(const Pattern& p, Vocabulary& voc, Scope& scope) {
  CPattern c;
  for (const PatternNode& n : p.nodes) {
    int slot = scope.find(n.var);
    if (slot < 0) slot = scope.add(n.var);
    c.slots.push_back(slot);
    c.types.push_back(voc.type(n.type));
    c.names.push_back(n.var);
  }
  for (const PatternEdge& e : p.edges)
    c.edges.push_back(CEdge{scope.find(e.from), scope.find(e.to), voc.label(e.label), e.negated});
  return c;
}

void CPattern::plan(const std::vector<bool>& prebound) {
  steps.clear();
  initial_checks.clear();
  std::vector<bool> bound(slots.size(), false);
  auto var_of = [&](int slot) {
    for (std::size_t k = 0; k < slots.size(); ++k)
      if (slots[k] == slot) return static_cast<int>(k);
    return -1;  // a slot outside the pattern: bound by whoever matches it
  };
  auto is_bound = [&](int slot) {
    const int k = var_of(slot);
    return k < 0 || bound[k];
  };
  for (std::size_t k = 0; k < slots.size(); ++k) bound[k] = k < prebound.size() && prebound[k];
  std::vector<bool> checked(edges.size(), false);
  for (std::size_t i = 0; i < edges.size(); ++i)
    if (is_bound(edges[i].from) && is_bound(edges[i].to)) {
      initial_checks.push_back(static_cast<int>(i));
      checked[i] = true;
    }
  for (;;) {
    int best = -1, best_links = -1, best_any = -1;
    for (std::size_t k = 0; k < slots.size(); ++k) {
      if (bound[k]) continue;
      int links = 0, any = 0;
      for (const CEdge& e : edges) {
        const bool touches = e.from == slots[k] || e.to == slots[k];
        if (!touches) continue;
        ++any;
        const int other = e.from == slots[k] ? e.to : e.from;
        if (!e.negated && other != slots[k] && is_bound(other)) ++links;
      }
      if (links > best_links || (links == best_links && any > best_any)) {
        best = static_cast<int>(k);
        best_links = links;
        best_any = any;
      }
    }
    if (best < 0) break;
    Step st;
    st.var = best;
    const int slot = slots[best];
    for (std::size_t i = 0; i < edges.size(); ++i) {
      const CEdge& e = edges[i];
      if (e.negated || (e.from != slot && e.to != slot)) continue;
      const int other = e.from == slot ? e.to : e.from;
      if (other != slot && is_bound(other)) {
        st.via = static_cast<int>(i);
        break;
      }
    }
    bound[best] = true;
    for (std::size_t i = 0; i < edges.size(); ++i)
      if (!checked[i] && is_bound(edges[i].from) && is_bound(edges[i].to)) {
        st.checks.push_back(static_cast<int>(i));
        checked[i] = true;
      }
    steps.push_back(std::move(st));
  }
}

namespace {

bool edge_ok(const State& s, const CEdge& e, const Binding& b) {
  return s.has_edge(b[e.from], b[e.to], e.label) != e.negated;
}

bool match_step(const State& s, const Vocabulary& voc, const CPattern& p, std::size_t i, Binding& b,
                const std::function<bool(Binding&)>& each) {
  if (i == p.steps.size()) return each(b);
  const CPattern::Step& st = p.steps[i];
  const int slot = p.slots[st.var];
  const TypeIx type = p.types[st.var];
  auto try_node = [&](NodeIx n) {
    if (!s.alive(n) || !voc.is_a(s.type(n), type)) return true;
    for (int other : p.slots)
      if (other != slot && b[other] == n) return true;  // injective
    b[slot] = n;
    for (int c : st.checks)
      if (!edge_ok(s, p.edges[c], b)) {
        b[slot] = kNoNode;
        return true;
      }
    const bool go_on = match_step(s, voc, p, i + 1, b, each);
    b[slot] = kNoNode;
    return go_on;
  };
  if (st.via >= 0) {
    const CEdge& e = p.edges[st.via];
    if (e.from == slot) {
      auto [lo, hi] = s.in(b[e.to], e.label);
      for (auto* q = lo; q != hi; ++q)
        if (!try_node(q->to)) return false;
    } else {
      auto [lo, hi] = s.out(b[e.from], e.label);
      for (auto* q = lo; q != hi; ++q)
        if (!try_node(q->to)) return false;
    }
    return true;
  }
  for (NodeIx n = 0; n < s.size(); ++n)
    if (!try_node(n)) return false;
  return true;
}

}  // namespace

bool match(const State& s, const Vocabulary& voc, const CPattern& p, Binding& b,
           const std::function<bool(Binding&)>& each) {
  // Variables bound before matching: alive, typed, distinct.
  for (std::size_t k = 0; k < p.slots.size(); ++k) {
    const NodeIx n = b[p.slots[k]];
    if (n == kNoNode) continue;
    if (!s.alive(n) || !voc.is_a(s.type(n), p.types[k])) return true;
    for (std::size_t j = 0; j < k; ++j)
      if (b[p.slots[j]] == n) return true;
  }
  for (int c : p.initial_checks)
    if (!edge_ok(s, p.edges[c], b)) return true;
  return match_step(s, voc, p, 0, b, each);
}

}  // namespace quiver::agents::inline rules::symbolic
