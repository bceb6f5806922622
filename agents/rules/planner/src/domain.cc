// A grammar's active rules compiled for planning: matched and applied on symbolic states with AGM's meaning (the
// rewrite, then the effect), and what the heuristic knows of them.
#include "quiver/agents/rules/planner/domain.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace quiver::agents::inline rules::planner {

using symbolic::Binding;
using symbolic::CEdge;
using symbolic::CFormula;
using symbolic::CPattern;
using symbolic::kNoNode;
using symbolic::LabelIx;
using symbolic::NodeIx;
using symbolic::Scope;
using symbolic::State;
using symbolic::TypeIx;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

struct CEffect {
  Effect::Kind kind = Effect::Kind::kAll;
  std::vector<CEffect> kids;
  std::vector<std::pair<int, TypeIx>> vars;  // kForall
  bool distinct = false;
  CFormula condition;                        // kWhen
  CEdge edge;                                // kAddEdge, kRemoveEdge
  int slot = -1;                             // kCreate, kDelete, kRetype
  TypeIx type = 0;                           // kCreate, kRetype
};

// A forall of our dialect: every binding of `vars` matching `lhs` is rewritten into `rhs`
// (edges only: a forall that creates or deletes nodes is left out).
struct CForall {
  CPattern lhs;
  std::vector<int> var_slots;
  std::vector<CEdge> remove, add;
};

bool compile_effect(const Effect& e, symbolic::Vocabulary& voc, Scope& scope, CEffect& out, std::string& why) {
  out.kind = e.kind;
  auto slot = [&](const std::string& v) {
    const int s = scope.find(v);
    if (s < 0 && why.empty()) why = "effect names unknown variable '" + v + "'";
    return s;
  };
  switch (e.kind) {
    case Effect::Kind::kAll:
      for (const Effect& k : e.kids) {
        out.kids.emplace_back();
        if (!compile_effect(k, voc, scope, out.kids.back(), why)) return false;
      }
      return true;
    case Effect::Kind::kForall: {
      Scope inner = scope;
      out.distinct = e.distinct;
      for (const PatternNode& v : e.vars) out.vars.emplace_back(inner.add(v.var), voc.type(v.type));
      for (const Effect& k : e.kids) {
        out.kids.emplace_back();
        if (!compile_effect(k, voc, inner, out.kids.back(), why)) return false;
      }
      scope.slots = std::max(scope.slots, inner.slots);
      return true;
    }
    case Effect::Kind::kWhen: {
      if (!symbolic::compile(e.condition, voc, scope, out.condition, why)) return false;
      for (const Effect& k : e.kids) {
        out.kids.emplace_back();
        if (!compile_effect(k, voc, scope, out.kids.back(), why)) return false;
      }
      return true;
    }
    case Effect::Kind::kAddEdge:
    case Effect::Kind::kRemoveEdge:
      out.edge = CEdge{slot(e.edge.from), slot(e.edge.to), voc.label(e.edge.label), false};
      return out.edge.from >= 0 && out.edge.to >= 0;
    case Effect::Kind::kCreate:
      out.slot = scope.add(e.var);
      out.type = voc.type(e.type);
      return true;
    case Effect::Kind::kDelete:
      out.slot = slot(e.var);
      return out.slot >= 0;
    case Effect::Kind::kRetype:
      out.slot = slot(e.var);
      out.type = voc.type(e.type);
      return out.slot >= 0;
  }
  return false;
}

// What one application of an effect can change, for the heuristic's bounds.
void effect_bounds(const CEffect& e, bool in_forall, std::vector<int>& add, std::vector<int>& remove,
                   std::vector<int>& create, std::vector<std::pair<TypeIx, bool>>& created_types,
                   std::vector<TypeIx>& retyped_types) {
  auto bump = [&](std::vector<int>& v, std::size_t i) {
    if (v.size() <= i) v.resize(i + 1, 0);
    v[i] = in_forall ? RuleBounds::kUnbounded : std::min(RuleBounds::kUnbounded, v[i] + 1);
  };
  switch (e.kind) {
    case Effect::Kind::kAll:
    case Effect::Kind::kWhen:
      for (const CEffect& k : e.kids) effect_bounds(k, in_forall, add, remove, create, created_types, retyped_types);
      break;
    case Effect::Kind::kForall:
      for (const CEffect& k : e.kids) effect_bounds(k, true, add, remove, create, created_types, retyped_types);
      break;
    case Effect::Kind::kAddEdge:
      bump(add, e.edge.label);
      break;
    case Effect::Kind::kRemoveEdge:
      bump(remove, e.edge.label);
      break;
    case Effect::Kind::kCreate:
    case Effect::Kind::kRetype:
      bump(create, e.type);
      created_types.emplace_back(e.type, in_forall);
      if (e.kind == Effect::Kind::kRetype) retyped_types.push_back(e.type);
      break;
    case Effect::Kind::kDelete:
      break;
  }
}

}  // namespace

struct Domain::Compiled {
  std::string name;
  double cost = 1;
  double success = 1;
  bool hierarchical = false;
  int slots = 0;
  std::vector<std::pair<std::string, int>> vars;  // every variable of both sides, by name
  CPattern lhs;
  std::vector<std::pair<int, TypeIx>> create, retype;
  std::vector<int> remove_nodes;
  std::vector<CEdge> remove, add;
  std::vector<CEdge> add_between_matched;  // added links whose ends the left side matches
  std::optional<CFormula> precondition;
  std::optional<CEffect> effect;
  std::vector<CForall> foralls;
  CPattern rhs_goal;          // hierarchical: the right-hand side, kept variables prebound
  std::vector<int> kept;      // slots of variables on both sides
};

namespace {

void apply_effect(const State& before, State& next, const symbolic::Vocabulary& voc, const CEffect& e, Binding& b) {
  switch (e.kind) {
    case Effect::Kind::kAll:
      for (const CEffect& k : e.kids) apply_effect(before, next, voc, k, b);
      return;
    case Effect::Kind::kWhen:
      if (symbolic::eval(before, voc, e.condition, b))
        for (const CEffect& k : e.kids) apply_effect(before, next, voc, k, b);
      return;
    case Effect::Kind::kForall: {
      // Over the nodes alive after the rewrite (a snapshot: the body may change the state).
      std::vector<std::vector<NodeIx>> pools;
      for (auto [slot, t] : e.vars) {
        std::vector<NodeIx> pool;
        for (NodeIx n = 0; n < next.size(); ++n)
          if (next.alive(n) && voc.is_a(next.type(n), t)) pool.push_back(n);
        pools.push_back(std::move(pool));
      }
      std::vector<NodeIx> saved;
      for (auto [slot, t] : e.vars) saved.push_back(b[slot]);
      std::vector<NodeIx> outer;
      if (e.distinct)
        for (NodeIx n : b)
          if (n != kNoNode) outer.push_back(n);
      std::function<void(std::size_t)> rec = [&](std::size_t i) {
        if (i == e.vars.size()) {
          for (const CEffect& k : e.kids) apply_effect(before, next, voc, k, b);
          return;
        }
        for (NodeIx n : pools[i]) {
          if (e.distinct) {
            if (std::find(outer.begin(), outer.end(), n) != outer.end()) continue;
            bool used = false;
            for (std::size_t j = 0; j < i; ++j) used = used || b[e.vars[j].first] == n;
            if (used) continue;
          }
          b[e.vars[i].first] = n;
          rec(i + 1);
        }
      };
      rec(0);
      for (std::size_t i = 0; i < e.vars.size(); ++i) b[e.vars[i].first] = saved[i];
      return;
    }
    case Effect::Kind::kAddEdge:
      if (b[e.edge.from] != kNoNode && b[e.edge.to] != kNoNode) next.add_edge(b[e.edge.from], b[e.edge.to], e.edge.label);
      return;
    case Effect::Kind::kRemoveEdge:
      if (b[e.edge.from] != kNoNode && b[e.edge.to] != kNoNode)
        next.remove_edge(b[e.edge.from], b[e.edge.to], e.edge.label);
      return;
    case Effect::Kind::kCreate:
      b[e.slot] = next.add_node(e.type);
      return;
    case Effect::Kind::kDelete:
      if (b[e.slot] != kNoNode) next.delete_node(b[e.slot]);
      return;
    case Effect::Kind::kRetype:
      if (b[e.slot] != kNoNode && next.alive(b[e.slot])) next.retype(b[e.slot], e.type);
      return;
  }
}

// The rewrite and the effect of `r` at `b` (a match of its left-hand side in `s`).
State rewrite(const State& s, const symbolic::Vocabulary& voc, const Domain::Compiled& r, Binding& b) {
  State next = s;
  for (auto [slot, t] : r.create) b[slot] = next.add_node(t);
  for (auto [slot, t] : r.retype) next.retype(b[slot], t);
  for (int slot : r.remove_nodes) next.delete_node(b[slot]);
  for (const CEdge& e : r.remove) next.remove_edge(b[e.from], b[e.to], e.label);
  for (const CEdge& e : r.add) next.add_edge(b[e.from], b[e.to], e.label);
  for (const CForall& f : r.foralls) {
    symbolic::match(s, voc, f.lhs, b, [&](Binding& m) {
      // Our dialect's forall variables are nodes other than the rule's.
      for (int v : f.var_slots)
        for (int slot : r.lhs.slots)
          if (m[v] == m[slot]) return true;
      for (const CEdge& e : f.remove) next.remove_edge(m[e.from], m[e.to], e.label);
      for (const CEdge& e : f.add) next.add_edge(m[e.from], m[e.to], e.label);
      return true;
    });
  }
  if (r.effect) apply_effect(s, next, voc, *r.effect, b);
  return next;
}

// The guard's meaning of a rewrite: a link the right-hand side adds between matched nodes is
// absent before (a change that "adds" an existing link adds nothing, and so does not apply the
// rule).
bool applicable(const State& s, const symbolic::Vocabulary& voc, const Domain::Compiled& r, Binding& m) {
  for (const CEdge& e : r.add_between_matched)
    if (s.has_edge(m[e.from], m[e.to], e.label)) return false;
  return !r.precondition || symbolic::eval(s, voc, *r.precondition, m);
}

bool same_edge(const PatternEdge& a, const PatternEdge& b) {
  return a.from == b.from && a.to == b.to && a.label == b.label;
}

}  // namespace

Domain::Domain(const Grammar& g, symbolic::Vocabulary& voc) : voc_(&voc) {
  RuleBounds& rb = bounds_;
  for (const Rule& rule : g.rules) {
    if (!rule.active) continue;
    if (rule.kind == Rule::Kind::kCombo) {
      notes_.push_back("rule '" + rule.name + "' is a combo: planners do not use combos (nor does AGM's)");
      continue;
    }
    auto c = std::make_unique<Compiled>();
    c->name = rule.name;
    c->cost = rule.cost;
    c->success = rule.success;
    c->hierarchical = rule.kind == Rule::Kind::kHierarchical;
    Scope scope;
    c->lhs = symbolic::compile(rule.lhs, voc, scope);
    c->lhs.plan({});
    for (const PatternNode& n : rule.rhs.nodes) {
      const PatternNode* l = rule.lhs.node(n.var);
      if (!l) {
        c->create.emplace_back(scope.add(n.var), voc.type(n.type));
      } else {
        c->kept.push_back(scope.find(n.var));
        if (l->type != n.type) c->retype.emplace_back(scope.find(n.var), voc.type(n.type));
      }
    }
    for (const PatternNode& n : rule.lhs.nodes)
      if (!rule.rhs.node(n.var)) c->remove_nodes.push_back(scope.find(n.var));
    for (const PatternEdge& e : rule.lhs.edges) {
      if (e.negated) continue;
      bool kept = false;
      for (const PatternEdge& r : rule.rhs.edges) kept = kept || (same_edge(e, r) && !r.negated);
      if (!kept) c->remove.push_back(CEdge{scope.find(e.from), scope.find(e.to), voc.label(e.label), false});
    }
    for (const PatternEdge& e : rule.rhs.edges) {
      if (e.negated) continue;
      bool had = false;
      for (const PatternEdge& l : rule.lhs.edges) had = had || (same_edge(e, l) && !l.negated);
      if (!had) c->add.push_back(CEdge{scope.find(e.from), scope.find(e.to), voc.label(e.label), false});
      if (!had && rule.lhs.node(e.from) && rule.lhs.node(e.to)) c->add_between_matched.push_back(c->add.back());
    }
    std::string why;
    if (rule.precondition) {
      CFormula f;
      if (!symbolic::compile(*rule.precondition, voc, scope, f, why)) {
        notes_.push_back("rule '" + rule.name + "' is left out: its precondition: " + why);
        continue;
      }
      c->precondition = std::move(f);
    }
    if (rule.effect) {
      CEffect e;
      if (!compile_effect(*rule.effect, voc, scope, e, why)) {
        notes_.push_back("rule '" + rule.name + "' is left out: its effect: " + why);
        continue;
      }
      c->effect = std::move(e);
    }
    bool forall_ok = true;
    for (const ForallEffect& fa : rule.foralls) {
      CForall f;
      Scope inner = scope;
      for (const PatternNode& v : fa.vars) f.var_slots.push_back(inner.add(v.var));
      bool nodes_change = false;
      for (const PatternNode& n : fa.lhs.nodes) nodes_change = nodes_change || !fa.rhs.node(n.var);
      for (const PatternNode& n : fa.rhs.nodes) nodes_change = nodes_change || !fa.lhs.node(n.var);
      if (nodes_change) {
        notes_.push_back("rule '" + rule.name + "' is left out: a forall that creates or deletes nodes");
        forall_ok = false;
        break;
      }
      // The forall's variables, matched through its left side's edges from the rule's nodes.
      Pattern vars_only;
      vars_only.nodes = fa.vars;
      vars_only.edges = fa.lhs.edges;
      f.lhs = symbolic::compile(vars_only, voc, inner);
      std::vector<bool> pre;
      for (int s : f.lhs.slots)
        pre.push_back(std::find(f.var_slots.begin(), f.var_slots.end(), s) == f.var_slots.end());
      f.lhs.plan(pre);
      for (const PatternEdge& e : fa.lhs.edges) {
        bool kept = false;
        for (const PatternEdge& r : fa.rhs.edges) kept = kept || (same_edge(e, r) && r.negated == e.negated);
        if (!kept && !e.negated) f.remove.push_back(CEdge{inner.find(e.from), inner.find(e.to), voc.label(e.label)});
      }
      for (const PatternEdge& e : fa.rhs.edges) {
        bool had = false;
        for (const PatternEdge& l : fa.lhs.edges) had = had || (same_edge(e, l) && !l.negated);
        if (!had && !e.negated) f.add.push_back(CEdge{inner.find(e.from), inner.find(e.to), voc.label(e.label)});
      }
      scope.slots = std::max(scope.slots, inner.slots);
      c->foralls.push_back(std::move(f));
    }
    if (!forall_ok) continue;
    {
      Scope rs = scope;
      c->rhs_goal = symbolic::compile(rule.rhs, voc, rs);
      std::vector<bool> pre;
      for (int s : c->rhs_goal.slots) pre.push_back(std::find(c->kept.begin(), c->kept.end(), s) != c->kept.end());
      c->rhs_goal.plan(pre);
    }
    for (const PatternNode& n : rule.lhs.nodes) c->vars.emplace_back(n.var, scope.find(n.var));
    for (const PatternNode& n : rule.rhs.nodes)
      if (!rule.lhs.node(n.var)) c->vars.emplace_back(n.var, scope.find(n.var));
    std::sort(c->vars.begin(), c->vars.end());
    c->slots = scope.slots;

    // Heuristic bounds: what one application changes at most, per label and type.
    std::vector<int> add, remove, create;
    std::vector<std::pair<TypeIx, bool>> created_types;  // type, unbounded
    for (const CEdge& e : c->add) {
      if (add.size() <= e.label) add.resize(e.label + 1, 0);
      ++add[e.label];
    }
    for (const CEdge& e : c->remove) {
      if (remove.size() <= e.label) remove.resize(e.label + 1, 0);
      ++remove[e.label];
    }
    for (auto [slot, t] : c->create) created_types.emplace_back(t, false);
    std::vector<TypeIx> retyped_types;
    for (auto [slot, t] : c->retype) {
      created_types.emplace_back(t, false);
      retyped_types.push_back(t);
    }
    for (const CForall& f : c->foralls) {
      for (const CEdge& e : f.add) {
        if (add.size() <= e.label) add.resize(e.label + 1, 0);
        add[e.label] = RuleBounds::kUnbounded;
      }
      for (const CEdge& e : f.remove) {
        if (remove.size() <= e.label) remove.resize(e.label + 1, 0);
        remove[e.label] = RuleBounds::kUnbounded;
      }
    }
    if (c->effect) effect_bounds(*c->effect, false, add, remove, create, created_types, retyped_types);
    for (TypeIx t : retyped_types)
      for (std::size_t base = 0; base < voc.type_count(); ++base)
        if (voc.is_a(t, static_cast<TypeIx>(base))) {
          if (rb.retype_into.size() <= base) rb.retype_into.resize(base + 1, false);
          rb.retype_into[base] = true;
        }
    auto merge = [&](std::vector<int>& max, std::vector<double>& min, const std::vector<int>& mine) {
      if (max.size() < mine.size()) {
        max.resize(mine.size(), 0);
        min.resize(mine.size(), kInf);
      }
      for (std::size_t i = 0; i < mine.size(); ++i) {
        if (mine[i] == 0) continue;
        max[i] = std::max(max[i], mine[i]);
        min[i] = std::min(min[i], c->cost);
      }
    };
    merge(rb.max_add, rb.min_add, add);
    merge(rb.max_remove, rb.min_remove, remove);
    // Deleting a node removes its links, whatever their labels.
    bool deletes = !c->remove_nodes.empty();
    std::function<void(const CEffect&)> scan = [&](const CEffect& e) {
      deletes = deletes || e.kind == Effect::Kind::kDelete;
      for (const CEffect& k : e.kids) scan(k);
    };
    if (c->effect) scan(*c->effect);
    if (deletes) rb.min_delete = std::min(rb.min_delete, c->cost);
    // A created node of type t is a node of every base of t: count it for those too.
    std::vector<int> create_any;
    for (auto [t, unbounded] : created_types)
      for (std::size_t base = 0; base < voc.type_count(); ++base)
        if (voc.is_a(t, static_cast<TypeIx>(base))) {
          if (create_any.size() <= base) create_any.resize(base + 1, 0);
          create_any[base] = unbounded ? RuleBounds::kUnbounded : std::min(RuleBounds::kUnbounded, create_any[base] + 1);
        }
    merge(rb.max_create, rb.min_create, create_any);
    names_.push_back(c->name);
    rules_.push_back(std::move(c));
  }
}

Domain::~Domain() = default;
Domain::Domain(Domain&&) noexcept = default;
Domain& Domain::operator=(Domain&&) noexcept = default;

const std::vector<std::string>& Domain::rule_names() const { return names_; }
std::size_t Domain::rule_count() const { return rules_.size(); }
bool Domain::hierarchical(int rule) const { return rules_[rule]->hierarchical; }
double Domain::cost(int rule) const { return rules_[rule]->cost; }
double Domain::success(int rule) const { return rules_[rule]->success; }
const RuleBounds& Domain::bounds() const { return bounds_; }

void Domain::successors(const State& s, const std::vector<bool>& excluded, bool with_hierarchical,
                        const std::function<void(const Step&, State&&)>& each) const {
  for (std::size_t ri = 0; ri < rules_.size(); ++ri) {
    const Compiled& r = *rules_[ri];
    if ((ri < excluded.size() && excluded[ri]) || (r.hierarchical && !with_hierarchical)) continue;
    Binding b(r.slots, kNoNode);
    symbolic::match(s, *voc_, r.lhs, b, [&](Binding& m) {
      if (!applicable(s, *voc_, r, m)) return true;
      Binding full = m;
      State next = rewrite(s, *voc_, r, full);
      Step step;
      step.rule = static_cast<int>(ri);
      step.name = r.name;
      step.hierarchical = r.hierarchical;
      step.binding.reserve(r.vars.size());
      for (const auto& [var, slot] : r.vars) step.binding.emplace_back(var, full[slot]);
      each(step, std::move(next));
      return true;
    });
  }
}

std::optional<State> Domain::apply(const State& s, const Step& step) const {
  if (step.rule < 0 || static_cast<std::size_t>(step.rule) >= rules_.size()) return std::nullopt;
  const Compiled& r = *rules_[step.rule];
  Binding b(r.slots, kNoNode);
  for (const auto& entry : r.vars) {
    const auto& var = entry.first;
    const int slot = entry.second;
    auto it = std::find_if(step.binding.begin(), step.binding.end(), [&](const auto& p) { return p.first == var; });
    if (it == step.binding.end()) return std::nullopt;
    // Created variables are bound by the rewrite itself.
    const bool created = std::any_of(r.create.begin(), r.create.end(), [&](const auto& c) { return c.first == slot; });
    if (!created) b[slot] = it->second;
  }
  // The binding must be a match of the left-hand side.
  bool ok = false;
  Binding probe = b;
  for (int slot : r.lhs.slots) probe[slot] = kNoNode;
  symbolic::match(s, *voc_, r.lhs, probe, [&](Binding& m) {
    for (int slot : r.lhs.slots)
      if (m[slot] != b[slot]) return true;
    ok = applicable(s, *voc_, r, m);
    return !ok;
  });
  if (!ok) return std::nullopt;
  return rewrite(s, *voc_, r, b);
}

std::pair<const CPattern*, Binding> Domain::hierarchical_goal(const Step& step) const {
  const Compiled& r = *rules_[step.rule];
  Binding b(r.slots, kNoNode);
  for (const auto& [var, slot] : r.vars) {
    if (std::find(r.kept.begin(), r.kept.end(), slot) == r.kept.end()) continue;
    for (const auto& [v, n] : step.binding)
      if (v == var) b[slot] = n;
  }
  return {&r.rhs_goal, b};
}

double plan_cost(const Domain& d, const std::vector<Step>& steps) {
  double total = 0, sum = 0;
  for (const Step& s : steps) {
    const double c = d.cost(s.rule);
    sum += c;
    total += c + (1.0 - d.success(s.rule)) * sum;
  }
  return total;
}

std::string to_string(const Step& step, const symbolic::World& world) {
  std::string out = (step.hierarchical ? "*" : "") + step.name + "@{";
  bool first = true;
  for (const auto& [var, n] : step.binding) {
    out += (first ? "'" : ", '") + var + "': '" + world.label(n) + "'";
    first = false;
  }
  return out + "}";
}

}  // namespace quiver::agents::inline rules::planner
