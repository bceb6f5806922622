// Checking transactions and states against a grammar.
//
// A transaction's structural changes (nodes created, deleted or retyped, edges added or removed,
// RT moves) must be ONE rule application (with its effect, if it has one). Matching is anchored on the changed elements: every variable of
// a rule that a changed edge or node touches is bound by that change; the remaining (context)
// variables are bound by walking context edges from bound nodes. So the cost follows the rule's
// size (and node degrees), not the graph's size. Candidate rules are found by a signature index
// (the multiset of removed/added edge labels and the numbers of deleted/created nodes).

#include <algorithm>
#include <deque>
#include <map>
#include <set>
#include <unordered_map>

#include "grammar_changes.h"
#include "grammar_combo.h"
#include "grammar_effect.h"
#include "grammar_formula.h"
#include "quiver/agents/rules/grammar/grammar.h"

namespace quiver::agents::inline rules {

using internal::Binding;
using internal::Changes;
using internal::describe;
using internal::enumerate;
using internal::eval;
using internal::Guard;
using internal::guard_of;

using graph::EdgeKey;
using graph::Graph;
using graph::NodeId;
using graph::Symbol;
using graph::TxnOp;

namespace {

bool edge_in_pre(const Graph& g, const EdgeKey& e) { return g.has_edge(e.from, e.to, e.type); }

// ------------------------------------------------------------------ compiled rules

struct Compiled {
  const Rule* rule = nullptr;
  std::vector<std::string> vars;                  // slot -> variable
  std::vector<std::string> types;                 // slot -> type (the left-hand side's if both)
  std::unordered_map<std::string, int> slot;      // variable -> slot
  std::vector<int> deleted, created, kept;        // slots
  std::vector<int> retyped;                       // kept slots whose type changes
  std::vector<std::string> retype_to;             // ... into this type
  struct E {
    int from, to;
    Symbol label;
  };
  std::vector<E> removed, added, context, neg_pre, neg_post;
  /// Applied with the rewrite: AGM's effect, or our dialect's forall effects as one.
  std::optional<Effect> effect;
  /// The rule's own changes as index keys ("-label", "+label", "del", "cre", "ret"): a rule with
  /// an effect is tried on a change that has them all.
  std::vector<std::string> keys;
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
void intern(Effect& e) {
  e.edge.symbol = Symbol(e.edge.label);
  intern(e.condition);
  for (auto& k : e.kids) intern(k);
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
    if (r.effect) intern(*r.effect);
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
  std::deque<Rule> composed;  // the rules combo rules stand for (compose_combo)
  std::vector<Compiled> rules;
  std::vector<CompiledConstraint> constraints;
  std::unordered_map<std::string, std::vector<int>> by_signature;
  std::vector<int> with_effects;
  std::vector<std::string> notes;

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
  for (const Rule& r : impl_->g.rules) {
    switch (r.kind) {
      case Rule::Kind::kNormal: impl_->rules.push_back(compile(r)); break;
      case Rule::Kind::kHierarchical: break;  // a planner decomposes it: no change applies it
      case Rule::Kind::kCombo:
        for (Rule& step : internal::compose_combo(impl_->g, r, impl_->notes)) {
          impl_->composed.push_back(std::move(step));
          impl_->rules.push_back(compile(impl_->composed.back()));
        }
        break;
    }
  }
  for (const Constraint& c : impl_->g.constraints) impl_->constraints.push_back(compile(c));
  for (int i = 0; i < static_cast<int>(impl_->rules.size()); ++i) {
    if (impl_->rules[i].effect) impl_->with_effects.push_back(i);
    else impl_->by_signature[impl_->rules[i].signature].push_back(i);
  }
}
GrammarChecker::~GrammarChecker() = default;
GrammarChecker::GrammarChecker(GrammarChecker&&) noexcept = default;
GrammarChecker& GrammarChecker::operator=(GrammarChecker&&) noexcept = default;
const Grammar& GrammarChecker::grammar() const { return impl_->g; }
const std::vector<std::string>& GrammarChecker::notes() const { return impl_->notes; }

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
    enum { kRemoved, kAdded, kDeleted, kCreated, kRetyped } kind;
    int index;
  };
  std::vector<Ob> obs;
  for (int i = 0; i < static_cast<int>(r.removed.size()); ++i) obs.push_back({Ob::kRemoved, i});
  for (int i = 0; i < static_cast<int>(r.added.size()); ++i) obs.push_back({Ob::kAdded, i});
  for (int i = 0; i < static_cast<int>(r.deleted.size()); ++i) obs.push_back({Ob::kDeleted, i});
  for (int i = 0; i < static_cast<int>(r.created.size()); ++i) obs.push_back({Ob::kCreated, i});
  for (int i = 0; i < static_cast<int>(r.retyped.size()); ++i) obs.push_back({Ob::kRetyped, i});
  std::vector<bool> used_removed(c.removed.size()), used_added(c.added.size());
  std::vector<NodeId> deleted(c.deleted.begin(), c.deleted.end());
  std::vector<NodeId> created, retyped;
  for (const auto& [id, t] : c.created) created.push_back(id);
  for (const auto& [id, t] : c.retyped) retyped.push_back(id);
  std::vector<bool> used_deleted(deleted.size()), used_created(created.size()), used_retyped(retyped.size());

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
    const bool del = ob.kind == Ob::kDeleted, ret = ob.kind == Ob::kRetyped;
    const int s = del ? r.deleted[ob.index] : ret ? r.retyped[ob.index] : r.created[ob.index];
    auto& pool = del ? deleted : ret ? retyped : created;
    auto& taken = del ? used_deleted : ret ? used_retyped : used_created;
    bool any = false;
    for (std::size_t i = 0; i < pool.size(); ++i) {
      if (taken[i]) continue;
      if (ret && !types.is_a(c.retyped.at(pool[i]), r.retype_to[ob.index])) {
        note(progress, "it retypes '" + r.vars[s] + "' to " + r.retype_to[ob.index] + ", but the change makes " +
                           gr.name_of(pool[i]) + " a " + c.retyped.at(pool[i]));
        continue;
      }
      any = true;
      bool was = bound[s];
      if (!bind(s, pool[i], progress)) continue;
      taken[i] = true;
      if (oblige(k + 1)) return true;
      taken[i] = false;
      if (!was) unbind(s);
    }
    if (!any && !ret)
      note(progress, std::string("it ") + (del ? "deletes" : "creates") + " a " + r.types[s] + " ('" + r.vars[s] +
                         "') that this change does not");
    if (!any && ret && pool.empty())
      note(progress, "it retypes '" + r.vars[s] + "' (a " + r.types[s] + ") to " + r.retype_to[ob.index] +
                         ", which this change does not");
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
    if (r.effect) {
      // The rewrite, then the effect over its outcome: together exactly the change.
      internal::Outcome out;
      for (const auto& e : r.removed) out.edges[ref(e)] = false;
      for (const auto& e : r.added) out.edges[ref(e)] = true;
      for (int s : r.deleted) out.deleted.insert(slot[s]);
      for (int s : r.created) out.created[slot[s]] = c.created.at(slot[s]);
      for (int s : r.retyped) out.retyped[slot[s]] = c.retyped.at(slot[s]);
      internal::apply_effect(gr, types, *r.effect, b, out);
      std::string why;
      if (!internal::outcome_is(gr, types, out, c, why)) {
        note(progress + 4, (r.rule->foralls.empty() ? "with its effect, " : "with its forall effects, ") + why);
        return false;
      }
    } else {
      auto same = [&](const std::vector<Compiled::E>& want, std::vector<EdgeKey> have) {
        if (want.size() != have.size()) return false;
        std::vector<EdgeKey> w;
        for (const auto& e : want) w.push_back(ref(e));
        std::sort(w.begin(), w.end(), graph::canonical_less);
        std::sort(have.begin(), have.end(), graph::canonical_less);
        return w == have;
      };
      if (!same(r.removed, c.removed) || !same(r.added, c.added)) {
        note(progress + 4, "the change does more than the rule");
        return false;
      }
      if (r.deleted.size() != c.deleted.size() || r.created.size() != c.created.size() ||
          r.retyped.size() != c.retyped.size()) {
        note(progress + 4, "the change creates, deletes or retypes other nodes than the rule");
        return false;
      }
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
  Changes c = internal::extract(g, gr, ops);
  if (!c.unruled.empty())
    return make_error(ErrorCode::kRefused, "grammar '" + g.name + "': " + c.unruled);
  if (!c.structural()) return {};
  std::vector<std::string> rl, al;
  for (const auto& e : c.removed) rl.push_back(e.type.str());
  for (const auto& e : c.added) al.push_back(e.type.str());
  std::vector<int> candidates;
  if (auto it = impl_->by_signature.find(signature(rl, al, c.deleted.size(), c.created.size(), c.retyped.size()));
      it != impl_->by_signature.end())
    candidates = it->second;
  if (!impl_->with_effects.empty()) {
    // A rule with an effect is tried when the change has every change of its own.
    std::unordered_map<std::string, int> have;
    for (const auto& l : rl) ++have["-" + l];
    for (const auto& l : al) ++have["+" + l];
    have["del"] = static_cast<int>(c.deleted.size());
    have["cre"] = static_cast<int>(c.created.size());
    have["ret"] = static_cast<int>(c.retyped.size());
    for (int i : impl_->with_effects) {
      std::unordered_map<std::string, int> need;
      bool fits = true;
      for (const std::string& k : impl_->rules[i].keys) {
        auto it = have.find(k);
        fits = fits && it != have.end() && ++need[k] <= it->second;
      }
      if (fits) candidates.push_back(i);
    }
  }
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
      for (std::size_t i = 0; i < closest->retyped.size(); ++i)
        what += (what.empty() ? "" : ", ") + std::string("retype ") + closest->vars[closest->retyped[i]] + " to " +
                closest->retype_to[i];
      msg += "; closest rule '" + closest->rule->name + "' does: " + what;
    }
  } else {
    msg += "; closest rule '" + closest->rule->name + "' fails: " + closest_attempt.why;
  }
  return make_error(ErrorCode::kRefused, msg);
}

Status GrammarChecker::Impl::verify_claim(const Graph& gr, const Changes& c, const std::string& rule,
                                          const std::vector<std::pair<std::string, NodeId>>& binding) const {
  // A combo rule stands for several compiled rules (one per choice of optional steps): the
  // claim's variables tell which.
  std::optional<Status> last;
  for (const Compiled& r : rules) {
    if (r.rule->name != rule) continue;
    std::vector<NodeId> fixed(r.vars.size());
    std::vector<bool> seen(r.vars.size());
    std::string wrong;
    for (const auto& [var, id] : binding) {
      auto it = r.slot.find(var);
      if (it == r.slot.end()) {
        wrong = "rule '" + rule + "' has no variable '" + var + "'";
        break;
      }
      fixed[it->second] = id;
      seen[it->second] = true;
    }
    for (std::size_t s = 0; s < seen.size() && wrong.empty(); ++s)
      if (!seen[s]) wrong = "the claim leaves variable '" + r.vars[s] + "' of rule '" + rule + "' unbound";
    if (!wrong.empty()) {
      if (!last) last = make_error(ErrorCode::kRefused, wrong);
      continue;
    }
    auto a = try_rule(gr, r, c, &fixed);
    if (a.ok) return {};
    last = make_error(ErrorCode::kRefused, "the change does not apply rule '" + rule + "': " + a.why);
  }
  if (last) return *last;
  if (const Rule* h = g.rule(rule); h && h->kind == Rule::Kind::kHierarchical)
    return make_error(ErrorCode::kRefused, "rule '" + rule +
                                               "' is hierarchical: a planner decomposes it into other rules, and no "
                                               "single change applies it");
  return make_error(ErrorCode::kRefused, "grammar '" + g.name + "' has no rule '" + rule + "'");
}

Status GrammarChecker::verify(const Graph& gr, const std::vector<TxnOp>& ops, const RuleMatch& claim) const {
  Changes c = internal::extract(impl_->g, gr, ops);
  if (!c.unruled.empty()) return make_error(ErrorCode::kRefused, "grammar '" + impl_->g.name + "': " + c.unruled);
  if (!c.structural() && claim.rule.empty()) return {};
  return impl_->verify_claim(gr, c, claim.rule, claim.binding);
}

Status GrammarChecker::verify_delta(const Graph& before, const graph::GraphDelta& d) const {
  const Grammar& g = impl_->g;
  Changes c = internal::extract_delta(g, before, d);
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
        enumerate(gr, types, cc.rest[i], true, cc.guard.formula, cc.guard.edges, b, [&](Binding& m) {
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
