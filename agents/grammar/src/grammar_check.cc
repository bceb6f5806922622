// Checking transactions and states against a grammar.
//
// A transaction's structural changes (nodes created or deleted, edges added or removed, RT moves)
// must be ONE rule application. Matching is anchored on the changed elements: every variable of
// a rule that a changed edge or node touches is bound by that change; the remaining (context)
// variables are bound by walking context edges from bound nodes. So the cost follows the rule's
// size (and node degrees), not the graph's size. Candidate rules are found by a signature index
// (the multiset of removed/added edge labels and the numbers of deleted/created nodes).

#include <algorithm>
#include <map>
#include <set>
#include <unordered_map>

#include "quiver/agents/grammar/grammar.h"

namespace quiver::agents {

using graph::EdgeKey;
using graph::Graph;
using graph::NodeId;
using graph::Symbol;
using graph::TxnOp;

namespace {

// ------------------------------------------------------------------ the change set

// Edges of a change are graph::EdgeKey, ordered by graph::canonical_less (types by text, not by
// symbol index, which depends on interning order).
using EdgeMap = std::map<EdgeKey, bool, decltype(&graph::canonical_less)>;

struct Changes {
  std::map<NodeId, std::string> created;  // id -> type
  std::set<NodeId> deleted;
  std::vector<EdgeKey> added, removed;
  std::string unruled;  // first change that needs an 'allow' the grammar lacks
  // Notes `what()` as the unruled change unless `ok` (first: an allowed change builds no message
  // and looks nothing up) or one is noted already.
  template <class What>
  void need(bool ok, const What& what) {
    if (!ok && unruled.empty()) unruled = what();
  }
  bool structural() const { return !created.empty() || !deleted.empty() || !added.empty() || !removed.empty(); }
};

bool edge_in_pre(const Graph& g, const EdgeKey& e) { return g.has_edge(e.from, e.to, e.type); }

// System attributes ("__lock", ...) belong to the runtime, not to the domain grammar.
bool system_attr(Symbol a) { return a.str().rfind("__", 0) == 0; }

Changes extract(const Grammar& gr, const Graph& g, const std::vector<TxnOp>& ops) {
  Changes c;
  EdgeMap state(graph::canonical_less);               // edge -> present after the ops so far
  std::map<NodeId, std::optional<NodeId>> rt_parent;  // child -> parent after the ops so far
  auto present = [&](const EdgeKey& e) {
    auto it = state.find(e);
    return it != state.end() ? it->second : edge_in_pre(g, e);
  };
  auto parent_of = [&](NodeId child) -> std::optional<NodeId> {
    auto it = rt_parent.find(child);
    return it != rt_parent.end() ? it->second : g.rt_parent(child);
  };
  const Symbol rt = graph::symbols::rt();
  for (const TxnOp& op : ops) {
    switch (op.kind) {
      case TxnOp::Kind::kCreateNode: c.created[op.node] = op.type.str(); break;
      case TxnOp::Kind::kDeleteNode:
        if (c.created.erase(op.node) == 0) c.deleted.insert(op.node);
        break;
      case TxnOp::Kind::kSetAttr:
      case TxnOp::Kind::kRemoveAttr:
        c.need(gr.allow_attributes || system_attr(op.attr) || c.created.count(op.node), [&] {
          return "attribute '" + op.attr.str() + "' of " + g.name_of(op.node) +
                 " changes but the grammar has no 'allow attributes'";
        });
        break;
      case TxnOp::Kind::kInsertEdge: {
        EdgeKey e{op.node, op.other, op.type};
        c.need(gr.allow_attributes || op.attrs.empty() || !present(e), [] {
          return std::string("edge attributes change but the grammar has no 'allow attributes'");
        });
        state[e] = true;
        break;
      }
      case TxnOp::Kind::kDeleteEdge:
        state[EdgeKey{op.node, op.other, op.type}] = false;
        break;
      case TxnOp::Kind::kSetEdgeAttr:
      case TxnOp::Kind::kRemoveEdgeAttr:
        c.need(gr.allow_attributes || !edge_in_pre(g, EdgeKey{op.node, op.other, op.type}), [&] {
          return "edge attribute '" + op.attr.str() +
                 "' changes but the grammar has no 'allow attributes'";
        });
        break;
      case TxnOp::Kind::kSetRt: {
        auto old = parent_of(op.node);
        if (old && *old == op.other) {
          c.need(gr.allow_rt_poses || c.created.count(op.node), [&] {
            return "the RT pose of " + g.name_of(op.node) +
                   " changes but the grammar has no 'allow rt-poses'";
          });
          break;
        }
        rt_parent[op.node] = op.other;
        if (gr.allow_rt_moves) break;
        if (old) state[EdgeKey{*old, op.node, rt}] = false;
        state[EdgeKey{op.other, op.node, rt}] = true;
        break;
      }
      case TxnOp::Kind::kRemoveRt: {
        auto old = parent_of(op.node);
        rt_parent[op.node] = std::nullopt;
        if (old && !gr.allow_rt_moves) state[EdgeKey{*old, op.node, rt}] = false;
        break;
      }
    }
  }
  for (const auto& [e, now] : state) {
    if (c.deleted.count(e.from) || c.deleted.count(e.to)) continue;  // goes with its node
    bool pre = edge_in_pre(g, e);
    if (now && !pre) c.added.push_back(e);
    if (!now && pre) c.removed.push_back(e);
  }
  return c;
}

// The structural changes a delta makes to `g` (the receiver's state before merging it).
Changes extract_delta(const Grammar& gr, const Graph& g, const graph::GraphDelta& d) {
  Changes c;
  const Symbol rt = graph::symbols::rt();
  for (const auto& n : d.nodes) {
    if (n.has_header && !g.has_node(n.id) && !g.context().contains(n.id.dot)) c.created[n.id] = n.type.str();
    if (n.removed && g.has_node(n.id)) c.deleted.insert(n.id);
  }
  for (const auto& n : d.nodes) {
    const bool fresh = c.created.count(n.id) != 0;
    if (!gr.allow_attributes && !fresh && !n.removed)
      for (std::uint32_t i = n.attrs.begin; i < n.attrs.end; ++i)
        c.need(system_attr(d.attrs[i].name), [&] {
          return "attribute '" + d.attrs[i].name.str() +
                 "' changes but the grammar has no 'allow attributes'";
        });
    const auto old = g.rt_parent(n.id);
    for (std::uint32_t i = n.claim_added.begin; i < n.claim_added.end; ++i) {
      const graph::RtClaim& cl = d.claims[i].value;
      if (old && !cl.parent.is_null() && *old == cl.parent) continue;
      if (gr.allow_rt_moves) continue;
      if (old) c.removed.push_back(EdgeKey{*old, n.id, rt});
      if (!cl.parent.is_null()) c.added.push_back(EdgeKey{cl.parent, n.id, rt});
    }
    c.need(gr.allow_rt_poses || n.samples.empty() || fresh, [] {
      return std::string("an RT pose changes but the grammar has no 'allow rt-poses'");
    });
  }
  for (const auto& e : d.edges) {
    if (c.deleted.count(e.key.from) || c.deleted.count(e.key.to)) continue;
    const bool pre = g.has_edge(e.key.from, e.key.to, e.key.type);
    EdgeKey ref{e.key.from, e.key.to, e.key.type};
    if (!pre && !e.added.empty()) c.added.push_back(ref);
    else if (pre && e.added.empty() && !e.removed.empty()) c.removed.push_back(ref);
    else if (pre && !gr.allow_attributes) {
      for (std::uint32_t i = e.attrs.begin; i < e.attrs.end; ++i)
        c.need(d.attrs[i].added.empty(), [] {
          return std::string("edge attributes change but the grammar has no 'allow attributes'");
        });
    }
  }
  return c;
}

std::string describe(const Graph& g, const EdgeKey& e,
                     const std::map<NodeId, std::string>& created) {
  auto name = [&](NodeId n) {
    std::string s = g.name_of(n);
    if (s.empty()) s = created.count(n) ? "new " + created.at(n) : n.to_string();
    return s;
  };
  return name(e.from) + " -[" + e.type.str() + "]-> " + name(e.to);
}

std::string describe(const Graph& g, const Changes& c) {
  std::string s;
  auto add = [&](const std::string& x) { s += (s.empty() ? "" : ", ") + x; };
  for (const auto& [id, type] : c.created) add("create a " + type);
  for (NodeId n : c.deleted) add("delete " + g.name_of(n));
  for (const auto& e : c.removed) add("remove " + describe(g, e, c.created));
  for (const auto& e : c.added) add("add " + describe(g, e, c.created));
  return s;
}

// ------------------------------------------------------------------ compiled rules

// A pattern's edges as a formula, and the positive ones (in order), which anchor candidates.
struct Guard {
  Formula formula;
  std::vector<const PatternEdge*> edges;
};
Guard guard_of(const Pattern& p);

// A forall effect: its guard, and the edges it removes and adds (the same for every match).
struct CompiledForall {
  const ForallEffect* effect = nullptr;
  Guard guard;
  std::vector<const PatternEdge*> removed, added;
};

struct Compiled {
  const Rule* rule = nullptr;
  std::vector<std::string> vars;                  // slot -> variable
  std::vector<std::string> types;                 // slot -> type
  std::unordered_map<std::string, int> slot;      // variable -> slot
  std::vector<int> deleted, created, kept;        // slots
  struct E {
    int from, to;
    Symbol label;
  };
  std::vector<E> removed, added, context, neg_pre, neg_post;
  std::vector<CompiledForall> foralls;
  std::string signature;
};

// "from->to(label)", the way messages name a rule's edge.
std::string edge_text(const Compiled& r, const Compiled::E& e) {
  return r.vars[e.from] + "->" + r.vars[e.to] + "(" + e.label.str() + ")";
}

// True if `p` has the (positive) edge `e`.
bool pattern_has_edge(const Pattern& p, const PatternEdge& e) {
  for (const auto& x : p.edges)
    if (!x.negated && x.from == e.from && x.to == e.to && x.label == e.label) return true;
  return false;
}

std::string signature(std::vector<std::string> removed, std::vector<std::string> added, std::size_t ndel,
                      std::size_t ncre) {
  std::sort(removed.begin(), removed.end());
  std::sort(added.begin(), added.end());
  std::string s = std::to_string(ndel) + "/" + std::to_string(ncre);
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
  for (const ForallEffect& fe : r.foralls) {
    CompiledForall cf{&fe, guard_of(fe.lhs), {}, {}};
    for (const auto& e : fe.lhs.edges)
      if (!e.negated && !pattern_has_edge(fe.rhs, e)) cf.removed.push_back(&e);
    for (const auto& e : fe.rhs.edges)
      if (!e.negated && !pattern_has_edge(fe.lhs, e)) cf.added.push_back(&e);
    c.foralls.push_back(std::move(cf));
  }
  c.signature = signature(rl, al, c.deleted.size(), c.created.size());
  return c;
}

// ------------------------------------------------------------------ formulas

bool compare(const graph::Value& v, CompareOp op, const graph::Value& lit) {
  auto as_double = [](const graph::Value& x, double& out) {
    switch (x.type()) {
      case graph::ValueType::kInt32: out = *x.get_if<std::int32_t>(); return true;
      case graph::ValueType::kInt64: out = static_cast<double>(*x.get_if<std::int64_t>()); return true;
      case graph::ValueType::kUInt32: out = *x.get_if<std::uint32_t>(); return true;
      case graph::ValueType::kUInt64: out = static_cast<double>(*x.get_if<std::uint64_t>()); return true;
      case graph::ValueType::kFloat: out = *x.get_if<float>(); return true;
      case graph::ValueType::kDouble: out = *x.get_if<double>(); return true;
      default: return false;
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
    case CompareOp::kEq: return cmp == 0;
    case CompareOp::kNe: return cmp != 0;
    case CompareOp::kLt: return cmp < 0;
    case CompareOp::kLe: return cmp <= 0;
    case CompareOp::kGt: return cmp > 0;
    case CompareOp::kGe: return cmp >= 0;
  }
  return false;
}

using Binding = std::unordered_map<std::string, NodeId>;

// Candidate nodes for a fresh variable of `type`, anchored when possible: neighbours of bound
// nodes along edges of `body` that mention the variable; otherwise every node of the type.
std::vector<NodeId> candidates(const Graph& g, const TypeSystem& types, const std::string& var, const std::string& type,
                               const std::vector<const PatternEdge*>& edges, const Binding& b) {
  std::vector<NodeId> out;
  bool anchored = false;
  for (const PatternEdge* e : edges) {
    if (e->negated) continue;
    if (e->to == var && b.count(e->from)) {
      for (const EdgeKey& k : g.edges_from(b.at(e->from), e->symbol)) out.push_back(k.to);
      anchored = true;
      break;
    }
    if (e->from == var && b.count(e->to)) {
      for (const EdgeKey& k : g.edges_to(b.at(e->to), e->symbol)) out.push_back(k.from);
      anchored = true;
      break;
    }
  }
  if (!anchored) out = g.nodes();  // unanchored variable: scan (documented cost)
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

bool eval(const Graph& g, const TypeSystem& types, const Formula& f, Binding& b);

// Enumerates bindings of `vars` (injective, distinct from the bound nodes) for which `guard`
// holds; calls `each` until it returns false. Returns false if stopped early. `edges` are the
// guard's (collect_edges), which anchor the candidates.
bool enumerate(const Graph& g, const TypeSystem& types, const std::vector<PatternNode>& vars,
               std::size_t i, const Formula& guard, const std::vector<const PatternEdge*>& edges,
               Binding& b, const std::function<bool(Binding&)>& each) {
  if (i == vars.size()) {
    if (!eval(g, types, guard, b)) return true;
    return each(b);
  }
  for (NodeId n : candidates(g, types, vars[i].var, vars[i].type, edges, b)) {
    bool used = false;
    for (const auto& [v, m] : b) used = used || m == n;
    if (used) continue;
    b[vars[i].var] = n;
    bool go_on = enumerate(g, types, vars, i + 1, guard, edges, b, each);
    b.erase(vars[i].var);
    if (!go_on) return false;
  }
  return true;
}
bool enumerate(const Graph& g, const TypeSystem& types, const std::vector<PatternNode>& vars,
               const Guard& guard, Binding& b, const std::function<bool(Binding&)>& each) {
  return enumerate(g, types, vars, 0, guard.formula, guard.edges, b, each);
}
bool enumerate(const Graph& g, const TypeSystem& types, const std::vector<PatternNode>& vars,
               const Formula& guard, Binding& b, const std::function<bool(Binding&)>& each) {
  std::vector<const PatternEdge*> edges;
  collect_edges(guard, edges);
  return enumerate(g, types, vars, 0, guard, edges, b, each);
}

bool eval(const Graph& g, const TypeSystem& types, const Formula& f, Binding& b) {
  switch (f.kind) {
    case Formula::Kind::kTrue: return true;
    case Formula::Kind::kFalse: return false;
    case Formula::Kind::kAnd:
      for (const auto& k : f.kids)
        if (!eval(g, types, k, b)) return false;
      return true;
    case Formula::Kind::kOr:
      for (const auto& k : f.kids)
        if (eval(g, types, k, b)) return true;
      return false;
    case Formula::Kind::kNot: return !eval(g, types, f.kids[0], b);
    case Formula::Kind::kEdge:
      return edge_in_pre(g, EdgeKey{b.at(f.edge.from), b.at(f.edge.to), f.edge.symbol});
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
      bool found = false;
      enumerate(g, types, f.vars, f.kids[0], b, [&](Binding&) {
        found = true;
        return false;
      });
      return found;
    }
    case Formula::Kind::kForall: {
      bool all = true;
      enumerate(g, types, f.vars, f.kids[0], b, [&](Binding& inner) {
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

// A constraint with its guard and, per variable of its pattern, the other variables: an anchor
// bound to that variable leaves those to enumerate.
struct CompiledConstraint {
  const Constraint* con = nullptr;
  Guard guard;
  std::vector<std::vector<PatternNode>> rest;
};

CompiledConstraint compile(const Constraint& con) {
  CompiledConstraint c{&con, guard_of(con.forbid), {}};
  for (const PatternNode& pv : con.forbid.nodes) {
    std::vector<PatternNode>& rest = c.rest.emplace_back();
    for (const auto& x : con.forbid.nodes)
      if (x.var != pv.var) rest.push_back(x);
  }
  return c;
}

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
void intern(Grammar& g) {
  for (Rule& r : g.rules) {
    intern(r.lhs);
    intern(r.rhs);
    if (r.precondition) intern(*r.precondition);
    for (ForallEffect& fe : r.foralls) {
      intern(fe.lhs);
      intern(fe.rhs);
    }
  }
  for (Constraint& c : g.constraints) {
    intern(c.forbid);
    if (c.where) intern(*c.where);
  }
}

}  // namespace

// ------------------------------------------------------------------ the checker

struct GrammarChecker::Impl {
  Grammar g;
  std::vector<Compiled> rules;
  std::vector<CompiledConstraint> constraints;
  std::unordered_map<std::string, std::vector<int>> by_signature;
  std::vector<int> with_foralls;

  // The outcome of trying one rule: success, or how far it got and why it stopped.
  struct Attempt {
    bool ok = false;
    int progress = 0;
    std::string why;
    std::vector<NodeId> slots;
  };

  Attempt try_rule(const Graph& gr, const Compiled& r, const Changes& c, const std::vector<NodeId>* fixed) const;
  // Checks `c` against the named rule with the claimed binding (no search).
  Status verify_claim(const Graph& gr, const Changes& c, const std::string& rule,
                      const std::vector<std::pair<std::string, NodeId>>& binding) const;
  // violations_around(), over every constraint or only those named `only`.
  std::vector<Violation> violations_around(const Graph& gr, const std::vector<NodeId>& anchors,
                                           const std::string* only) const;
};

GrammarChecker::GrammarChecker(Grammar g) : impl_(std::make_unique<Impl>()) {
  impl_->g = std::move(g);
  intern(impl_->g);
  for (const Rule& r : impl_->g.rules) impl_->rules.push_back(compile(r));
  for (const Constraint& c : impl_->g.constraints) impl_->constraints.push_back(compile(c));
  for (int i = 0; i < static_cast<int>(impl_->rules.size()); ++i) {
    if (!impl_->rules[i].rule->foralls.empty()) impl_->with_foralls.push_back(i);
    else impl_->by_signature[impl_->rules[i].signature].push_back(i);
  }
}
GrammarChecker::~GrammarChecker() = default;
GrammarChecker::GrammarChecker(GrammarChecker&&) noexcept = default;
GrammarChecker& GrammarChecker::operator=(GrammarChecker&&) noexcept = default;
const Grammar& GrammarChecker::grammar() const { return impl_->g; }

GrammarChecker::Impl::Attempt GrammarChecker::Impl::try_rule(const Graph& gr, const Compiled& r, const Changes& c,
                                                             const std::vector<NodeId>* fixed) const {
  const TypeSystem& types = g.types;
  const int n = static_cast<int>(r.vars.size());
  Attempt best;
  std::vector<NodeId> slot(n);
  std::vector<bool> bound(n, false);
  std::set<NodeId> used;
  auto type_of = [&](NodeId id) -> const std::string& {
    auto it = c.created.find(id);
    return it != c.created.end() ? it->second : gr.type_of(id).str();
  };
  auto note = [&](int progress, std::string why) {
    if (progress > best.progress || best.why.empty()) {
      best.progress = progress;
      best.why = std::move(why);
    }
  };
  auto bind = [&](int s, NodeId id, int progress) -> bool {
    if (bound[s]) {
      if (slot[s] == id) return true;
      note(progress, "variable '" + r.vars[s] + "' would have to be two nodes at once");
      return false;
    }
    if (used.count(id)) {
      note(progress, "two variables would match the same node " + gr.name_of(id) + " (matches are injective)");
      return false;
    }
    if (!types.is_a(type_of(id), r.types[s])) {
      note(progress, "'" + r.vars[s] + "' must be a " + r.types[s] + " but " +
                         (gr.name_of(id).empty() ? id.to_string() : gr.name_of(id)) + " is a " + type_of(id));
      return false;
    }
    bound[s] = true;
    slot[s] = id;
    used.insert(id);
    return true;
  };
  auto unbind = [&](int s) {
    bound[s] = false;
    used.erase(slot[s]);
  };

  // Obligations: each rule change maps to a distinct change of the transaction.
  struct Ob {
    enum { kRemoved, kAdded, kDeleted, kCreated } kind;
    int index;
  };
  std::vector<Ob> obs;
  for (int i = 0; i < static_cast<int>(r.removed.size()); ++i) obs.push_back({Ob::kRemoved, i});
  for (int i = 0; i < static_cast<int>(r.added.size()); ++i) obs.push_back({Ob::kAdded, i});
  for (int i = 0; i < static_cast<int>(r.deleted.size()); ++i) obs.push_back({Ob::kDeleted, i});
  for (int i = 0; i < static_cast<int>(r.created.size()); ++i) obs.push_back({Ob::kCreated, i});
  std::vector<bool> used_removed(c.removed.size()), used_added(c.added.size());
  std::vector<NodeId> deleted(c.deleted.begin(), c.deleted.end());
  std::vector<NodeId> created;
  for (const auto& [id, t] : c.created) created.push_back(id);
  std::vector<bool> used_deleted(deleted.size()), used_created(created.size());

  std::function<bool(std::size_t)> context;  // binds the remaining variables and checks the rest
  std::function<bool(std::size_t)> oblige = [&](std::size_t k) -> bool {
    const int progress = static_cast<int>(k) * 10;
    if (k == obs.size()) return context(0);
    const Ob& ob = obs[k];
    if (ob.kind == Ob::kRemoved || ob.kind == Ob::kAdded) {
      const Compiled::E& e = ob.kind == Ob::kRemoved ? r.removed[ob.index] : r.added[ob.index];
      const auto& pool = ob.kind == Ob::kRemoved ? c.removed : c.added;
      auto& taken = ob.kind == Ob::kRemoved ? used_removed : used_added;
      bool any = false;
      for (std::size_t i = 0; i < pool.size(); ++i) {
        if (taken[i] || pool[i].type != e.label) continue;
        any = true;
        bool fb = bound[e.from], tb = bound[e.to];
        if (!bind(e.from, pool[i].from, progress)) continue;
        if (!bind(e.to, pool[i].to, progress)) {
          if (!fb) unbind(e.from);
          continue;
        }
        taken[i] = true;
        if (oblige(k + 1)) return true;
        taken[i] = false;
        if (!tb) unbind(e.to);
        if (!fb) unbind(e.from);
      }
      if (!any)
        note(progress, std::string("it ") + (ob.kind == Ob::kRemoved ? "removes" : "adds") +
                           " an edge (" + e.label.str() + ") " + r.vars[e.from] + "->" +
                           r.vars[e.to] + " that this change does not");
      return false;
    }
    const bool del = ob.kind == Ob::kDeleted;
    const int s = del ? r.deleted[ob.index] : r.created[ob.index];
    auto& pool = del ? deleted : created;
    auto& taken = del ? used_deleted : used_created;
    bool any = false;
    for (std::size_t i = 0; i < pool.size(); ++i) {
      if (taken[i]) continue;
      any = true;
      bool was = bound[s];
      if (!bind(s, pool[i], progress)) continue;
      taken[i] = true;
      if (oblige(k + 1)) return true;
      taken[i] = false;
      if (!was) unbind(s);
    }
    if (!any) note(progress, std::string("it ") + (del ? "deletes" : "creates") + " a " + r.types[s] + " ('" + r.vars[s] + "') that this change does not");
    return false;
  };

  context = [&](std::size_t) -> bool {
    const int progress = static_cast<int>(obs.size()) * 10 + 5;
    // Bind unbound (kept) variables by walking context edges from bound ones.
    int pick = -1;
    const Compiled::E* via = nullptr;
    for (const auto& e : r.context) {
      if (bound[e.from] != bound[e.to]) {
        pick = bound[e.from] ? e.to : e.from;
        via = &e;
        break;
      }
    }
    if (pick < 0)
      for (int s = 0; s < n; ++s)
        if (!bound[s]) {
          pick = s;
          break;
        }
    if (pick >= 0) {
      std::vector<NodeId> cand;
      if (via && via->label == graph::symbols::rt()) {
        if (via->to == pick)
          cand = gr.rt_children(slot[via->from]);
        else if (auto p = gr.rt_parent(slot[via->to]))
          cand.push_back(*p);
      } else if (via) {
        if (via->to == pick)
          for (const EdgeKey& k : gr.edges_from(slot[via->from], via->label)) cand.push_back(k.to);
        else
          for (const EdgeKey& k : gr.edges_to(slot[via->to], via->label)) cand.push_back(k.from);
      } else {
        cand = gr.nodes();  // a context variable no edge reaches: scan
      }
      bool any = false;
      for (NodeId id : cand) {
        if (c.deleted.count(id) || c.created.count(id)) continue;
        if (!bind(pick, id, progress)) continue;
        any = true;
        if (context(0)) return true;
        unbind(pick);
      }
      if (!any)
        note(progress, via ? "it needs an edge " + edge_text(r, *via) + " that the graph lacks"
                           : "no node can play '" + r.vars[pick] + "' (a " + r.types[pick] + ")");
      return false;
    }
    // Everything bound: context edges present (and kept), negatives absent, precondition true.
    auto ref = [&](const Compiled::E& e) { return EdgeKey{slot[e.from], slot[e.to], e.label}; };
    auto removed_now = [&](const EdgeKey& e) {
      return std::find(c.removed.begin(), c.removed.end(), e) != c.removed.end();
    };
    auto added_now = [&](const EdgeKey& e) {
      return std::find(c.added.begin(), c.added.end(), e) != c.added.end();
    };
    for (const auto& e : r.context) {
      EdgeKey x = ref(e);
      bool endpoint_deleted = c.deleted.count(x.from) || c.deleted.count(x.to);
      if (!edge_in_pre(gr, x) || (!endpoint_deleted && removed_now(x))) {
        note(progress + 1, "it needs an edge " + edge_text(r, e) + " that the graph lacks");
        return false;
      }
    }
    for (const auto& e : r.neg_pre)
      if (edge_in_pre(gr, ref(e))) {
        note(progress + 2, "it forbids the edge " + edge_text(r, e) + ", which exists");
        return false;
      }
    for (const auto& e : r.neg_post) {
      EdgeKey x = ref(e);
      if ((edge_in_pre(gr, x) && !removed_now(x)) || added_now(x)) {
        note(progress + 2, "its result forbids the edge " + edge_text(r, e));
        return false;
      }
    }
    Binding b;
    for (int s = 0; s < n; ++s) b[r.vars[s]] = slot[s];
    if (r.rule->precondition && !eval(gr, types, *r.rule->precondition, b)) {
      note(progress + 3, "its precondition does not hold");
      return false;
    }
    // Forall effects: every match of each effect's left side must be rewritten too, and the
    // rule plus its effects must account for exactly the transaction's changes.
    std::vector<EdgeKey> want_removed, want_added;
    for (const auto& e : r.removed) want_removed.push_back(ref(e));
    for (const auto& e : r.added) want_added.push_back(ref(e));
    for (const CompiledForall& cf : r.foralls) {
      Binding fb = b;
      enumerate(gr, types, cf.effect->vars, cf.guard, fb, [&](Binding& m) {
        for (const PatternEdge* e : cf.removed)
          want_removed.push_back(EdgeKey{m.at(e->from), m.at(e->to), e->symbol});
        for (const PatternEdge* e : cf.added)
          want_added.push_back(EdgeKey{m.at(e->from), m.at(e->to), e->symbol});
        return true;
      });
    }
    auto same = [](std::vector<EdgeKey> a, std::vector<EdgeKey> b) {
      std::sort(a.begin(), a.end(), graph::canonical_less);
      std::sort(b.begin(), b.end(), graph::canonical_less);
      return a == b;
    };
    if (!same(want_removed, c.removed) || !same(want_added, c.added)) {
      note(progress + 4, r.rule->foralls.empty() ? "the change does more than the rule"
                                                 : "its forall effects do not match the change exactly");
      return false;
    }
    if (r.deleted.size() != c.deleted.size() || r.created.size() != c.created.size()) {
      note(progress + 4, "the change creates or deletes other nodes than the rule");
      return false;
    }
    best.ok = true;
    best.slots = slot;
    return true;
  };

  if (fixed) {
    // Verification of a claimed binding: pre-bind every variable, then run the same checks.
    for (int s = 0; s < n; ++s)
      if (!bind(s, (*fixed)[s], 0)) return best;
  }
  oblige(0);
  return best;
}

Status GrammarChecker::check(const Graph& gr, const std::vector<TxnOp>& ops, RuleMatch* match) const {
  const Grammar& g = impl_->g;
  Changes c = extract(g, gr, ops);
  if (!c.unruled.empty())
    return make_error(ErrorCode::kRefused, "grammar '" + g.name + "': " + c.unruled);
  if (!c.structural()) return {};
  std::vector<std::string> rl, al;
  for (const auto& e : c.removed) rl.push_back(e.type.str());
  for (const auto& e : c.added) al.push_back(e.type.str());
  std::vector<int> candidates;
  if (auto it = impl_->by_signature.find(signature(rl, al, c.deleted.size(), c.created.size())); it != impl_->by_signature.end())
    candidates = it->second;
  candidates.insert(candidates.end(), impl_->with_foralls.begin(), impl_->with_foralls.end());
  const Compiled* closest = nullptr;
  Impl::Attempt closest_attempt;
  for (int i : candidates) {
    const Compiled& r = impl_->rules[i];
    Impl::Attempt a = impl_->try_rule(gr, r, c, nullptr);
    if (a.ok) {
      if (match) {
        match->rule = r.rule->name;
        match->binding.clear();
        for (std::size_t s = 0; s < r.vars.size(); ++s) match->binding.emplace_back(r.vars[s], a.slots[s]);
        std::sort(match->binding.begin(), match->binding.end());
      }
      return {};
    }
    if (!closest || a.progress > closest_attempt.progress) {
      closest = &r;
      closest_attempt = a;
    }
  }
  // No rule matched. Name the closest: the candidate that got furthest, or else the rule whose
  // changes share the most edge labels with this one.
  std::string msg = "grammar '" + g.name + "' has no rule for: " + describe(gr, c);
  if (!closest) {
    int best = -1;
    std::multiset<std::string> mine;
    for (const auto& e : c.removed) mine.insert("-" + e.type.str());
    for (const auto& e : c.added) mine.insert("+" + e.type.str());
    for (const Compiled& r : impl_->rules) {
      int score = 0;
      for (const auto& e : r.removed) score += mine.count("-" + e.label.str()) ? 2 : 0;
      for (const auto& e : r.added) score += mine.count("+" + e.label.str()) ? 2 : 0;
      score -= static_cast<int>(r.removed.size() + r.added.size());
      if (score > best) {
        best = score;
        closest = &r;
      }
    }
    if (closest) {
      std::string what;
      for (const auto& e : closest->removed)
        what += (what.empty() ? "" : ", ") + std::string("remove ") + edge_text(*closest, e);
      for (const auto& e : closest->added)
        what += (what.empty() ? "" : ", ") + std::string("add ") + edge_text(*closest, e);
      for (int s : closest->deleted) what += (what.empty() ? "" : ", ") + std::string("delete ") + closest->vars[s];
      for (int s : closest->created) what += (what.empty() ? "" : ", ") + std::string("create ") + closest->vars[s];
      msg += "; closest rule '" + closest->rule->name + "' does: " + what;
    }
  } else {
    msg += "; closest rule '" + closest->rule->name + "' fails: " + closest_attempt.why;
  }
  return make_error(ErrorCode::kRefused, msg);
}

Status GrammarChecker::Impl::verify_claim(const Graph& gr, const Changes& c, const std::string& rule,
                                          const std::vector<std::pair<std::string, NodeId>>& binding) const {
  const Compiled* r = nullptr;
  for (const auto& x : rules)
    if (x.rule->name == rule) r = &x;
  if (!r) return make_error(ErrorCode::kRefused, "grammar '" + g.name + "' has no rule '" + rule + "'");
  std::vector<NodeId> fixed(r->vars.size());
  std::vector<bool> seen(r->vars.size());
  for (const auto& [var, id] : binding) {
    auto it = r->slot.find(var);
    if (it == r->slot.end()) return make_error(ErrorCode::kRefused, "rule '" + rule + "' has no variable '" + var + "'");
    fixed[it->second] = id;
    seen[it->second] = true;
  }
  for (std::size_t s = 0; s < seen.size(); ++s)
    if (!seen[s])
      return make_error(ErrorCode::kRefused, "the claim leaves variable '" + r->vars[s] + "' of rule '" + rule + "' unbound");
  auto a = try_rule(gr, *r, c, &fixed);
  if (!a.ok) return make_error(ErrorCode::kRefused, "the change does not apply rule '" + rule + "': " + a.why);
  return {};
}

Status GrammarChecker::verify(const Graph& gr, const std::vector<TxnOp>& ops, const RuleMatch& claim) const {
  Changes c = extract(impl_->g, gr, ops);
  if (!c.unruled.empty()) return make_error(ErrorCode::kRefused, "grammar '" + impl_->g.name + "': " + c.unruled);
  if (!c.structural() && claim.rule.empty()) return {};
  return impl_->verify_claim(gr, c, claim.rule, claim.binding);
}

Status GrammarChecker::verify_delta(const Graph& before, const graph::GraphDelta& d) const {
  const Grammar& g = impl_->g;
  Changes c = extract_delta(g, before, d);
  if (!c.unruled.empty()) return make_error(ErrorCode::kRefused, "grammar '" + g.name + "': " + c.unruled);
  if (!c.structural()) return {};
  if (d.rule.empty())
    return make_error(ErrorCode::kRefused, "a structural change (" + describe(before, c) + ") claims no rule");
  if (d.rule == "repair") {
    // Repairs only delete edges, and only the agent a constraint names may make them (agent
    // ids derive from names).
    bool designated = false;
    for (const Constraint& con : g.constraints)
      designated = designated || (!con.repair_agent.empty() && fnv1a64(con.repair_agent) == d.origin.agent);
    if (!designated) return make_error(ErrorCode::kRefused, "a repair from an agent no constraint designates");
    if (!c.added.empty() || !c.created.empty() || !c.deleted.empty())
      return make_error(ErrorCode::kRefused, "a repair that does more than delete edges (" + describe(before, c) + ")");
    return {};
  }
  return impl_->verify_claim(before, c, d.rule, d.binding);
}

// ------------------------------------------------------------------ constraints

std::string Violation::to_string(const Graph& g) const {
  std::string s = constraint + "(";
  for (std::size_t i = 0; i < binding.size(); ++i)
    s += (i ? ", " : "") + binding[i].first + "=" + g.name_of(binding[i].second);
  return s + ")";
}

std::vector<Violation> GrammarChecker::violations_around(const Graph& gr, const std::vector<NodeId>& anchors) const {
  return impl_->violations_around(gr, anchors, nullptr);
}

bool GrammarChecker::still_violated(const Graph& gr, const Violation& v) const {
  // Every binding over v's nodes maps some variable to its first node, so a search anchored
  // there alone finds them all (and so reports the same smallest one). A deleted node matches
  // nothing.
  if (v.binding.empty()) return false;
  for (const Violation& w : impl_->violations_around(gr, {v.binding.front().second}, &v.constraint))
    if (w == v) return true;
  return false;
}

std::vector<Violation> GrammarChecker::Impl::violations_around(const Graph& gr,
                                                               const std::vector<NodeId>& anchors,
                                                               const std::string* only) const {
  const TypeSystem& types = g.types;
  // A violation is identified by its constraint and its set of nodes; of the bindings that
  // produce it (symmetric patterns give several), the smallest is reported, so every replica
  // reports the same one whatever order it found them in.
  std::map<std::pair<std::string, std::vector<NodeId>>, Violation> found;
  for (const CompiledConstraint& cc : constraints) {
    const Constraint& con = *cc.con;
    if (only != nullptr && con.name != *only) continue;
    for (NodeId anchor : anchors) {
      if (!gr.has_node(anchor)) continue;
      const std::string& anchor_type = gr.type_of(anchor).str();
      for (std::size_t i = 0; i < con.forbid.nodes.size(); ++i) {
        const PatternNode& pv = con.forbid.nodes[i];
        if (!types.is_a(anchor_type, pv.type)) continue;
        Binding b;
        b[pv.var] = anchor;
        enumerate(gr, types, cc.rest[i], cc.guard, b, [&](Binding& m) {
          if (con.where && !eval(gr, types, *con.where, m)) return true;
          Violation v;
          v.constraint = con.name;
          std::vector<NodeId> nodes;
          for (const auto& [var, id] : m) {
            nodes.push_back(id);
            v.binding.emplace_back(var, id);
          }
          std::sort(nodes.begin(), nodes.end());
          std::sort(v.binding.begin(), v.binding.end());
          auto [it, fresh] = found.try_emplace({con.name, std::move(nodes)}, v);
          if (!fresh && v.binding < it->second.binding) it->second = std::move(v);
          return true;
        });
      }
    }
  }
  std::vector<Violation> out;
  for (auto& [key, v] : found) out.push_back(std::move(v));
  std::sort(out.begin(), out.end(), [](const Violation& a, const Violation& b) {
    if (a.constraint != b.constraint) return a.constraint < b.constraint;
    return a.binding < b.binding;
  });
  return out;
}

std::vector<Violation> GrammarChecker::all_violations(const Graph& gr) const { return violations_around(gr, gr.nodes()); }

}  // namespace quiver::agents
