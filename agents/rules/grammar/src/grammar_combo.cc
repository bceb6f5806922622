// Combo rules as plain rules: each choice of optional steps composed into one rule the checker matches like any
// other.
#include "grammar_combo.h"

#include <algorithm>
#include <map>
#include <optional>
#include <set>
#include <tuple>

#include "grammar_lexer.h"

namespace quiver::agents::inline rules::internal {
namespace {

constexpr std::size_t kMaxOptionalSteps = 6;  // 2^6 variants at most

// Composes the steps of one choice; nullopt (and `why`) if they contradict each other.
class Composer {
 public:
  Composer(const Grammar& g, const Rule& combo) : g_(g), combo_(combo) {}

  std::optional<Rule> compose(const std::vector<const ComboAtom*>& steps, std::string& why) {
    // Classes of step variables: union-find over "alias.var", restricted to the chosen steps.
    std::map<std::string, const Rule*> chosen;  // alias -> step rule
    for (const ComboAtom* a : steps) chosen[a->alias] = g_.rule(a->rule);
    for (const auto& cls : combo_.equivalences) {
      const ComboVar* first = nullptr;
      for (const ComboVar& x : cls) {
        auto step = chosen.find(x.alias);
        if (step == chosen.end() ||
            (!step->second->lhs.node(x.var) && !step->second->rhs.node(x.var)))
          continue;
        if (!first)
          first = &x;
        else
          unite(key(first->alias, first->var), key(x.alias, x.var));
      }
    }
    try {
      for (const ComboAtom* a : steps) step(*a, *g_.rule(a->rule));
    } catch (const std::string& e) {
      why = e;
      return std::nullopt;
    }
    return result();
  }

 private:
  enum class Edge : std::uint8_t { kPresent, kAbsent };
  struct Var {
    std::string name;
    bool original = false;  // a node of the state before the combo
    bool alive = false;
    std::string lhs_type, type;  // required before; now
  };
  using EdgeRef = std::tuple<int, int, std::string>;

  static std::string key(const std::string& alias, const std::string& var) {
    return alias + "." + var;
  }
  std::string find(const std::string& k) {
    auto it = parent_.find(k);
    if (it == parent_.end() || it->second == k) return k;
    return it->second = find(it->second);
  }
  void unite(const std::string& a, const std::string& b) {
    const std::string ra = find(a), rb = find(b);
    if (ra != rb) parent_[rb] = ra;
  }
  int var_of(const ComboAtom& a, const std::string& v) {
    const std::string root = find(key(a.alias, v));
    auto it = index_.find(root);
    if (it != index_.end()) return it->second;
    index_[root] = static_cast<int>(vars_.size());
    Var fresh;
    fresh.name = root;
    vars_.push_back(std::move(fresh));
    return static_cast<int>(vars_.size()) - 1;
  }
  [[noreturn]] void contradiction(const ComboAtom& a, const std::string& what) {
    throw "step '" + a.alias + "' (" + a.rule + ") " + what;
  }
  std::optional<Edge> state(const EdgeRef& e) const {
    auto it = edges_.find(e);
    if (it != edges_.end()) return it->second;
    const Var& f = vars_[std::get<0>(e)];
    const Var& t = vars_[std::get<1>(e)];
    if (!f.original || !t.original)
      return Edge::kAbsent;  // a node the combo made has only the edges it got
    return std::nullopt;     // unknown: the state before decides
  }
  void require(const ComboAtom& a, const EdgeRef& e, bool present) {
    const auto s = state(e);
    if (!s) {
      (present ? need_ : forbid_).insert(e);
      edges_[e] = present ? Edge::kPresent : Edge::kAbsent;
    } else if ((*s == Edge::kPresent) != present) {
      contradiction(a, std::string(present ? "needs" : "forbids") + " an edge " + std::get<2>(e) +
                           " that an earlier step " + (present ? "removed or never made" : "made"));
    }
  }
  static bool has(const Pattern& p, const PatternEdge& e) {
    for (const auto& x : p.edges)
      if (!x.negated && x.from == e.from && x.to == e.to && x.label == e.label) return true;
    return false;
  }

  void step(const ComboAtom& a, const Rule& r) {
    if (r.precondition || r.effect || !r.foralls.empty())
      contradiction(a, "has a precondition or an effect, which reads the states between the steps");
    std::set<int> seen;
    for (const PatternNode& n : r.lhs.nodes) {
      const int v = var_of(a, n.var);
      if (!seen.insert(v).second) contradiction(a, "matches two of its variables to one node");
      Var& x = vars_[v];
      if (!x.original && !x.alive && x.type.empty()) {  // first seen: a node of the state before
        x.original = x.alive = true;
        x.lhs_type = x.type = n.type;
        continue;
      }
      if (!x.alive) contradiction(a, "uses '" + n.var + "', a node an earlier step deleted");
      if (g_.types.is_a(x.type, n.type)) continue;
      if (x.original && x.type == x.lhs_type && g_.types.is_a(n.type, x.type)) {
        x.lhs_type = x.type = n.type;  // a narrower requirement on the node before
        continue;
      }
      contradiction(a, "needs '" + n.var + "' to be a " + n.type + ", but it is a " + x.type);
    }
    auto ref = [&](const PatternEdge& e) {
      return EdgeRef{var_of(a, e.from), var_of(a, e.to), e.label};
    };
    for (const PatternEdge& e : r.lhs.edges) require(a, ref(e), !e.negated);
    // The rewrite.
    for (const PatternNode& n : r.lhs.nodes)
      if (!r.rhs.node(n.var)) {
        const int v = var_of(a, n.var);
        vars_[v].alive = false;
        for (auto& [e, s] : edges_)
          if (std::get<0>(e) == v || std::get<1>(e) == v) s = Edge::kAbsent;
      }
    for (const PatternNode& n : r.rhs.nodes) {
      const int v = var_of(a, n.var);
      Var& x = vars_[v];
      if (const PatternNode* l = r.lhs.node(n.var)) {
        if (l->type != n.type) x.type = n.type;  // retyped
        continue;
      }
      if (x.original || x.alive)
        contradiction(a, "creates '" + n.var + "', which the equivalences make an existing node");
      x.alive = true;
      x.type = n.type;
    }
    for (const PatternEdge& e : r.lhs.edges)
      if (!e.negated && !has(r.rhs, e) && r.rhs.node(e.from) && r.rhs.node(e.to))
        edges_[ref(e)] = Edge::kAbsent;
    for (const PatternEdge& e : r.rhs.edges)
      if (!e.negated && !has(r.lhs, e)) {
        // A rule adds an edge that was not there (a change cannot add an existing edge): if the
        // state before decides, it must lack it.
        if (!state(ref(e))) forbid_.insert(ref(e));
        edges_[ref(e)] = Edge::kPresent;
      }
    for (const PatternEdge& e : r.rhs.edges)
      if (e.negated) require(a, ref(e), false);
  }

  Rule result() const {
    Rule out;
    out.name = combo_.name;
    out.kind = Rule::Kind::kNormal;
    out.active = combo_.active;
    out.cost = combo_.cost;
    out.file = combo_.file;
    out.loc = combo_.loc;
    for (const Var& v : vars_) {
      if (v.original)
        out.lhs.nodes.push_back(PatternNode{v.name, v.lhs_type, combo_.loc, std::nullopt});
      if (v.alive) out.rhs.nodes.push_back(PatternNode{v.name, v.type, combo_.loc, std::nullopt});
    }
    auto edge = [&](const EdgeRef& e, bool negated) {
      const std::string& label = std::get<2>(e);
      return PatternEdge{
          vars_[std::get<0>(e)].name, vars_[std::get<1>(e)].name, label, negated, combo_.loc,
          graph::Symbol(label)};
    };
    for (const EdgeRef& e : need_) out.lhs.edges.push_back(edge(e, false));
    for (const EdgeRef& e : forbid_) out.lhs.edges.push_back(edge(e, true));
    for (const auto& [e, s] : edges_)
      if (s == Edge::kPresent && vars_[std::get<0>(e)].alive && vars_[std::get<1>(e)].alive)
        out.rhs.edges.push_back(edge(e, false));
    return out;
  }

  const Grammar& g_;
  const Rule& combo_;
  std::map<std::string, std::string> parent_;
  std::map<std::string, int> index_;
  std::vector<Var> vars_;
  std::map<EdgeRef, Edge> edges_;    // what the steps so far know of an edge
  std::set<EdgeRef> need_, forbid_;  // what they require of the state before
};

}  // namespace

std::vector<Rule> compose_combo(const Grammar& g, const Rule& combo,
                                std::vector<std::string>& why) {
  // What AGM's planner would fail on when it tries the combo leaves the combo out; what it
  // ignores, we ignore too.
  auto note = [&](SourceLoc loc, const std::string& msg) {
    why.push_back(located(combo.file, loc, msg));
  };
  for (const ComboAtom& a : combo.atoms) {
    const Rule* step = g.rule(a.rule);
    if (!step || step->kind != Rule::Kind::kNormal) {
      note(a.loc, "combo rule '" + combo.name + "' uses rule '" + a.rule + "', which is " +
                      (!step                              ? "not defined"
                       : step->kind == Rule::Kind::kCombo ? "a combo"
                                                          : "hierarchical") +
                      ": the combo is left out (AGM's planner fails when it tries it)");
      return {};
    }
  }
  for (const auto& cls : combo.equivalences)
    for (const ComboVar& x : cls) {
      const auto atom = std::find_if(combo.atoms.begin(), combo.atoms.end(),
                                     [&](const ComboAtom& a) { return a.alias == x.alias; });
      if (atom == combo.atoms.end()) {
        std::string hint;
        for (const ComboAtom& a : combo.atoms)
          if (a.rule == x.alias)
            hint = " (did you mean '" + a.alias + "', the alias of rule '" + a.rule + "'?)";
        note(x.loc, "combo rule '" + combo.name + "' names alias '" + x.alias +
                        "', which none of its steps has" + hint +
                        ": the combo is left out (AGM's planner fails when it tries it)");
        return {};
      }
      const Rule* step = g.rule(atom->rule);
      if (!step->lhs.node(x.var) && !step->rhs.node(x.var))
        note(x.loc, "'" + x.alias + "." + x.var + "': rule '" + atom->rule + "' has no variable '" +
                        x.var + "': ignored, as AGM's planner does");
    }
  std::vector<const ComboAtom*> optional;
  for (const ComboAtom& a : combo.atoms)
    if (a.optional) optional.push_back(&a);
  const std::size_t choices =
      optional.size() <= kMaxOptionalSteps ? (std::size_t{1} << optional.size()) : 1;
  if (optional.size() > kMaxOptionalSteps)
    note(combo.loc, "combo rule '" + combo.name + "' has more than " +
                        std::to_string(kMaxOptionalSteps) +
                        " optional steps: only the choice of every step is checked");
  std::vector<Rule> out;
  for (std::size_t mask = 0; mask < choices; ++mask) {  // mask: the optional steps left out
    std::vector<const ComboAtom*> steps;
    for (const ComboAtom& a : combo.atoms) {
      const auto k = std::find(optional.begin(), optional.end(), &a) - optional.begin();
      if (!a.optional || !(mask >> k & 1U)) steps.push_back(&a);
    }
    if (steps.empty()) continue;
    std::string reason;
    std::optional<Rule> r = Composer(g, combo).compose(steps, reason);
    if (!r) {
      std::string which;
      for (const ComboAtom* a : steps) which += (which.empty() ? "" : " ") + a->alias;
      note(combo.loc, "combo rule '" + combo.name + "' with steps " + which + ": " + reason +
                          (reason.find("precondition or an effect") != std::string::npos
                               ? ": the combo is left out"
                               : ": that choice is left out"));
      if (reason.find("precondition or an effect") != std::string::npos) return {};
      continue;
    }
    out.push_back(std::move(*r));
  }
  return out;
}

}  // namespace quiver::agents::inline rules::internal
