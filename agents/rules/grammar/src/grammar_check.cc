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

#include "grammar_changes.h"
#include "grammar_combo.h"
#include "grammar_compiled.h"
#include "quiver/agents/rules/grammar/grammar.h"

namespace quiver::agents::inline rules {

using internal::Changes;
using internal::compile;
using internal::Compiled;
using internal::describe;
using internal::edge_text;
using internal::intern;
using internal::signature;

using graph::Graph;
using graph::NodeId;
using graph::TxnOp;

// ------------------------------------------------------------------ the checker

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

}  // namespace quiver::agents
