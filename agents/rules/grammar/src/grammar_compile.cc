// Grammars compiled for checking: each rule to slots, removed / added / context / negative
// edges and index keys (its signature), each constraint with its guard; symbols interned.

#include <algorithm>
#include <set>
#include <unordered_map>

#include "grammar_compiled.h"

namespace quiver::agents::inline rules {

using graph::Symbol;

namespace internal {

// "from->to(label)", the way messages name a rule's edge.
std::string edge_text(const Compiled& r, const Compiled::E& e) {
  return r.vars[e.from] + "->" + r.vars[e.to] + "(" + e.label.str() + ")";
}

namespace {

// True if `p` has the (positive) edge `e`.
bool pattern_has_edge(const Pattern& p, const PatternEdge& e) {
  for (const auto& x : p.edges)
    if (!x.negated && x.from == e.from && x.to == e.to && x.label == e.label) return true;
  return false;
}

}  // namespace

std::string signature(std::vector<std::string> removed, std::vector<std::string> added, std::size_t ndel,
                      std::size_t ncre, std::size_t nret) {
  std::sort(removed.begin(), removed.end());
  std::sort(added.begin(), added.end());
  std::string s = std::to_string(ndel) + "/" + std::to_string(ncre) + "/" + std::to_string(nret);
  for (const auto& r : removed) s += "|-" + r;
  for (const auto& a : added) s += "|+" + a;
  return s;
}

Compiled compile(const Rule& r) {
  Compiled c;
  c.rule = &r;
  auto add_var = [&](const PatternNode& n) {
    if (c.slot.count(n.var)) return;
    c.slot[n.var] = static_cast<int>(c.vars.size());
    c.vars.push_back(n.var);
    c.types.push_back(n.type);
  };
  for (const auto& n : r.lhs.nodes) add_var(n);
  for (const auto& n : r.rhs.nodes) add_var(n);
  for (const auto& n : r.lhs.nodes) (r.rhs.node(n.var) ? c.kept : c.deleted).push_back(c.slot[n.var]);
  for (const auto& n : r.rhs.nodes)
    if (!r.lhs.node(n.var)) c.created.push_back(c.slot[n.var]);
  std::vector<std::string> rl, al;
  for (const auto& e : r.lhs.edges) {
    Compiled::E ce{c.slot[e.from], c.slot[e.to], e.symbol};
    if (e.negated) c.neg_pre.push_back(ce);
    else if (pattern_has_edge(r.rhs, e))
      c.context.push_back(ce);
    else {
      // An edge of a deleted node goes with the node; it is matched, not counted as a removal.
      bool with_node = !r.rhs.node(e.from) || !r.rhs.node(e.to);
      if (with_node) c.context.push_back(ce);
      else {
        c.removed.push_back(ce);
        rl.push_back(e.label);
      }
    }
  }
  for (const auto& e : r.rhs.edges) {
    Compiled::E ce{c.slot[e.from], c.slot[e.to], e.symbol};
    if (e.negated) c.neg_post.push_back(ce);
    else if (!pattern_has_edge(r.lhs, e)) {
      c.added.push_back(ce);
      al.push_back(e.label);
    }
  }
  for (const auto& n : r.rhs.nodes)
    if (const PatternNode* l = r.lhs.node(n.var); l && l->type != n.type) {
      c.retyped.push_back(c.slot[n.var]);
      c.retype_to.push_back(n.type);
    }
  // Our forall effects are AGM effects: (forall V (when LHS (and removals additions))), with
  // V's nodes distinct from each other and from the rule's.
  Effect all;
  all.kind = Effect::Kind::kAll;
  for (const ForallEffect& fe : r.foralls) {
    Effect body;
    body.kind = Effect::Kind::kAll;
    for (const auto& e : fe.lhs.edges)
      if (!e.negated && !pattern_has_edge(fe.rhs, e)) {
        Effect x;
        x.kind = Effect::Kind::kRemoveEdge;
        x.edge = e;
        body.kids.push_back(std::move(x));
      }
    for (const auto& e : fe.rhs.edges)
      if (!e.negated && !pattern_has_edge(fe.lhs, e)) {
        Effect x;
        x.kind = Effect::Kind::kAddEdge;
        x.edge = e;
        body.kids.push_back(std::move(x));
      }
    Effect when;
    when.kind = Effect::Kind::kWhen;
    when.condition = internal::guard_of(fe.lhs).formula;
    when.kids.push_back(std::move(body));
    Effect forall;
    forall.kind = Effect::Kind::kForall;
    forall.vars = fe.vars;
    forall.distinct = true;
    forall.loc = fe.loc;
    forall.kids.push_back(std::move(when));
    all.kids.push_back(std::move(forall));
  }
  if (r.effect) all.kids.push_back(*r.effect);
  if (!all.kids.empty()) c.effect = std::move(all);
  for (const auto& l : rl) c.keys.push_back("-" + l);
  for (const auto& l : al) c.keys.push_back("+" + l);
  c.keys.insert(c.keys.end(), c.deleted.size(), "del");
  c.keys.insert(c.keys.end(), c.created.size(), "cre");
  c.keys.insert(c.keys.end(), c.retyped.size(), "ret");
  c.signature = signature(rl, al, c.deleted.size(), c.created.size(), c.retyped.size());
  return c;
}

CompiledConstraint compile(const Constraint& con) {
  CompiledConstraint c{&con, guard_of(con.forbid), {}};
  for (const PatternNode& pv : con.forbid.nodes) {
    std::vector<PatternNode>& rest = c.rest.emplace_back();
    for (const auto& x : con.forbid.nodes)
      if (x.var != pv.var) rest.push_back(x);
  }
  return c;
}

namespace {

// Sets the interned symbols of every label and attribute name (the parser does, but a grammar
// may be built by hand).
void intern(Pattern& p) {
  for (auto& e : p.edges) e.symbol = Symbol(e.label);
}
void intern(Formula& f) {
  f.edge.symbol = Symbol(f.edge.label);
  f.attr_symbol = Symbol(f.attr);
  for (auto& k : f.kids) intern(k);
}
void intern(Effect& e) {
  e.edge.symbol = Symbol(e.edge.label);
  intern(e.condition);
  for (auto& k : e.kids) intern(k);
}

}  // namespace

void intern(Grammar& g) {
  for (Rule& r : g.rules) {
    intern(r.lhs);
    intern(r.rhs);
    if (r.precondition) intern(*r.precondition);
    for (ForallEffect& fe : r.foralls) {
      intern(fe.lhs);
      intern(fe.rhs);
    }
    if (r.effect) intern(*r.effect);
  }
  for (Constraint& c : g.constraints) {
    intern(c.forbid);
    if (c.where) intern(*c.where);
  }
}

}  // namespace internal
}  // namespace quiver::agents
