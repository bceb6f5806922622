#pragma once
/// @file
/// A grammar's active rules compiled for planning: matched and applied on symbolic states
/// (agents/rules/symbolic), with AGM's meaning (docs/grammar.md, "AGM's dialect"): the rewrite
/// (created, retyped and deleted nodes, links removed and added), then the effect.
///
/// Passive rules are left out (perception agents make those changes, as in AGM's planner);
/// so are combo rules (AGM cannot plan with them either) and rules whose conditions read
/// attributes (a symbolic state has none): Domain::notes() names each.

#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "quiver/agents/rules/grammar/grammar.h"
#include "quiver/agents/rules/symbolic/match.h"
#include "quiver/agents/rules/symbolic/state.h"

namespace quiver::agents::inline rules::planner {

/// One action of a plan: a rule and the node each of its variables is bound to.
struct Step {
  int rule = -1;  ///< index into Domain::rules()
  std::string name;
  std::vector<std::pair<std::string, symbolic::NodeIx>> binding;  ///< every variable of both sides
  bool hierarchical = false;
  friend bool operator==(const Step&, const Step&) = default;
};

/// What the heuristic knows of the rules: per label and type, the most a single application
/// can change (kUnbounded when an effect's forall can change any number) and the cheapest rule
/// that changes it.
struct RuleBounds {
  static constexpr int kUnbounded = 1 << 29;
  std::vector<int> max_add, max_remove, max_create;     ///< per label, label, type
  std::vector<double> min_add, min_remove, min_create;  ///< cheapest cost doing it (inf: none)
  /// Per type: some rule can retype a node into it (or a subtype), so that links the node has
  /// may come to fit a mission's variables of that type.
  std::vector<bool> retype_into;
  /// The cheapest rule that deletes a node (and so any of its links); inf: none.
  double min_delete = std::numeric_limits<double>::infinity();
};

class Domain {
 public:
  struct Compiled;

  /// Compiles the active rules of `g`, interning their types and labels in `voc`.
  Domain(const Grammar& g, symbolic::Vocabulary& voc);
  ~Domain();
  Domain(Domain&&) noexcept;
  Domain& operator=(Domain&&) noexcept;

  /// Rules the planner uses, in the grammar's order.
  const std::vector<std::string>& rule_names() const;
  std::size_t rule_count() const;
  bool hierarchical(int rule) const;
  double cost(int rule) const;
  double success(int rule) const;
  /// Rules left out, and why.
  const std::vector<std::string>& notes() const { return notes_; }
  const RuleBounds& bounds() const;
  const symbolic::Vocabulary& vocabulary() const { return *voc_; }

  /// Calls `each(step, next)` for every application of every rule in `s` (rules in order, then
  /// matches in the order of node indices). `excluded[r]` skips rule r; hierarchical rules are
  /// skipped unless `with_hierarchical`.
  void successors(const symbolic::State& s, const std::vector<bool>& excluded, bool with_hierarchical,
                  const std::function<void(const Step&, symbolic::State&&)>& each) const;
  /// Applies `step` to `s`: nullopt when its rule does not apply there with that binding.
  std::optional<symbolic::State> apply(const symbolic::State& s, const Step& step) const;

  /// The goal of decomposing hierarchical `step`: its rule's right-hand side, with the
  /// variables of both sides fixed to the step's nodes. @returns the pattern, its binding.
  std::pair<const symbolic::CPattern*, symbolic::Binding> hierarchical_goal(const Step& step) const;

 private:
  symbolic::Vocabulary* voc_;
  std::vector<std::unique_ptr<Compiled>> rules_;
  std::vector<std::string> names_;
  std::vector<std::string> notes_;
  RuleBounds bounds_;
};

/// AGM's cost of a plan (agm-planner-notes.md §3): Σ c_i + (1 − p_i)·Σ_{j≤i} c_j.
double plan_cost(const Domain& d, const std::vector<Step>& steps);

/// "rule@{'var': 'node', ...}" as AGM's planner prints an action (nodes by World::label).
std::string to_string(const Step& step, const symbolic::World& world);

}  // namespace quiver::agents::inline rules::planner
