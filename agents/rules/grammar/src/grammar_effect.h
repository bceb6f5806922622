#pragma once
// Applying a rule's effect (effect.h) to the outcome of its rewrite, and comparing the result
// with what a change did.

#include <map>
#include <set>
#include <string>
#include <vector>

#include "grammar_changes.h"
#include "grammar_formula.h"
#include "quiver/agents/rules/grammar/effect.h"

namespace quiver::agents::inline rules::internal {

/// What a rule application leaves behind, as writes over the state before it.
struct Outcome {
  /// Edges written: present after the change or not (the last write stands).
  std::map<graph::EdgeKey, bool, decltype(&graph::canonical_less)> edges{graph::canonical_less};
  std::set<graph::NodeId> deleted;               ///< nodes of the state before that go
  std::map<graph::NodeId, std::string> created;  ///< nodes made, and their types
  std::map<graph::NodeId, std::string> retyped;  ///< nodes of the state before: their new type
  /// Nodes an effect creates: stand-in ids, matched to the change's new nodes at the end.
  std::vector<graph::NodeId> placeholders;

  bool alive(const graph::Graph& before, graph::NodeId n) const;
  /// The node's type after the change so far.
  std::string type_of(const graph::Graph& before, graph::NodeId n) const;
};

/// Applies `e` with the variables `b` binds (the rule's, after its rewrite) to `out`. `when`
/// conditions read `before`; `forall` ranges over the nodes alive in `out`.
void apply_effect(const graph::Graph& before, const TypeSystem& types, const Effect& e, Binding& b,
                  Outcome& out);

/// True if the change `c` is exactly `out`: the same edges added and removed, nodes deleted,
/// created (an effect's new nodes matched to the change's by type and edges) and retyped.
/// Otherwise false, with `why`.
bool outcome_is(const graph::Graph& before, const TypeSystem& types, const Outcome& out,
                const Changes& c, std::string& why);

}  // namespace quiver::agents::inline rules::internal
