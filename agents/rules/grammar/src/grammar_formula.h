#pragma once
// Evaluating formulas at a match, and enumerating the bindings of quantified variables, in the
// state a change starts from. Shared by rules, constraints and effects.

#include <functional>
#include <string>
#include <unordered_map>
#include <vector>

#include "quiver/agents/rules/grammar/grammar.h"

namespace quiver::agents::inline rules::internal {

using Binding = std::unordered_map<std::string, graph::NodeId>;

/// A formula with the positive edges of its top-level conjunction, which anchor the candidates
/// of quantified variables.
struct Guard {
  Formula formula;
  std::vector<const PatternEdge*> edges;
};
/// A pattern's edges as a guard (negative edges as `not`).
Guard guard_of(const Pattern& p);
/// The positive edges of `f`'s top-level conjunction (or `f` itself if it is an edge).
void collect_edges(const Formula& f, std::vector<const PatternEdge*>& out);

bool compare(const graph::Value& v, CompareOp op, const graph::Value& lit);

/// Candidate nodes for a fresh variable `var` of `type`: the neighbours of a bound node along
/// one of `edges` that mentions the variable, if any; otherwise every node of the type
/// (subtypes included). Filtered by type.
std::vector<graph::NodeId> candidates(const graph::Graph& g, const TypeSystem& types,
                                      const std::string& var, const std::string& type,
                                      const std::vector<const PatternEdge*>& edges,
                                      const Binding& b);

/// Enumerates the bindings of `vars` for which `guard` holds, calling `each` until it returns
/// false (then returns false). With `distinct`, the new nodes differ from each other and from
/// every node `b` binds; without, they range over every node of their type. A variable that
/// shadows one of `b` gets its old value back afterwards.
bool enumerate(const graph::Graph& g, const TypeSystem& types, const std::vector<PatternNode>& vars,
               bool distinct, const Formula& guard, const std::vector<const PatternEdge*>& edges,
               Binding& b, const std::function<bool(Binding&)>& each);

bool eval(const graph::Graph& g, const TypeSystem& types, const Formula& f, Binding& b);

}  // namespace quiver::agents::inline rules::internal
