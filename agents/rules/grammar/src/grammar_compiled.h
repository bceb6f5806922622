#pragma once
// Private: a grammar compiled for checking — rules as slots, edges and index keys, constraints
// with their guards — and the checker's state (GrammarChecker::Impl) that its parts share.

#include <deque>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "grammar_changes.h"
#include "grammar_effect.h"
#include "grammar_formula.h"
#include "quiver/agents/rules/grammar/grammar.h"

namespace quiver::agents::inline rules {
namespace internal {

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
    graph::Symbol label;
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
std::string edge_text(const Compiled& r, const Compiled::E& e);

/// A rule's index key: its numbers of deleted, created and retyped nodes and its removed and
/// added edge labels.
std::string signature(std::vector<std::string> removed, std::vector<std::string> added, std::size_t ndel,
                      std::size_t ncre, std::size_t nret);

Compiled compile(const Rule& r);

// A constraint with its guard and, per variable of its pattern, the other variables: an anchor
// bound to that variable leaves those to enumerate.
struct CompiledConstraint {
  const Constraint* con = nullptr;
  Guard guard;
  std::vector<std::vector<PatternNode>> rest;
};

CompiledConstraint compile(const Constraint& con);

/// Sets the interned symbols of every label and attribute name (the parser does, but a grammar
/// may be built by hand).
void intern(Grammar& g);

}  // namespace internal

struct GrammarChecker::Impl {
  Grammar g;
  std::deque<Rule> composed;  // the rules combo rules stand for (compose_combo)
  std::vector<internal::Compiled> rules;
  std::vector<internal::CompiledConstraint> constraints;
  std::unordered_map<std::string, std::vector<int>> by_signature;
  std::vector<int> with_effects;
  std::vector<std::string> notes;

  // The outcome of trying one rule: success, or how far it got and why it stopped.
  struct Attempt {
    bool ok = false;
    int progress = 0;
    std::string why;
    std::vector<graph::NodeId> slots;
  };

  Attempt try_rule(const graph::Graph& gr, const internal::Compiled& r, const internal::Changes& c,
                   const std::vector<graph::NodeId>* fixed) const;
  // Checks `c` against the named rule with the claimed binding (no search).
  Status verify_claim(const graph::Graph& gr, const internal::Changes& c, const std::string& rule,
                      const std::vector<std::pair<std::string, graph::NodeId>>& binding) const;
  // violations_around(), over every constraint or only those named `only`.
  std::vector<Violation> violations_around(const graph::Graph& gr,
                                           const std::vector<graph::NodeId>& anchors,
                                           const std::string* only) const;
};

}  // namespace quiver::agents
