#pragma once
/// @file
/// A rule's effect in AGM's PDDL-like language (`effect { (forall o:object (when (in o r)
/// (and (not (in o a)) (in o b)))) }`): changes applied together with the rule's rewrite, as
/// part of the same change.
///
/// Meaning (AGM's planner, generateAGGLPlannerCode.py): the rule's rewrite is applied first;
/// then the effect, in order. `forall` ranges over every node of the state after the rewrite
/// (of the type, subtypes included; the same node may play several variables); a `when`
/// condition is read in the state before the change; an edge adds it, `not` of an edge removes
/// it; `create`, `delete` and `retype` make, remove and retype a node. When two parts write
/// the same edge, the later one stands.

#include <cstdint>
#include <string>
#include <vector>

#include "quiver/agents/rules/grammar/pattern.h"

namespace quiver::agents::inline rules {

struct Effect {
  enum class Kind : std::uint8_t {
    kAll,         ///< `and`: every part, in order
    kForall,      ///< `forall`: the body for every binding of `vars`
    kWhen,        ///< `when`: the body if `condition` holds (before the change)
    kAddEdge,     ///< an edge: it exists after the change
    kRemoveEdge,  ///< `not` of an edge: it does not
    kCreate,      ///< `create v T`: a new node of type T, named v in what follows
    kDelete,      ///< `delete v`: the node of v goes, with its edges
    kRetype,      ///< `retype v T`: the node of v becomes a T
  };
  Kind kind = Kind::kAll;
  std::vector<Effect> kids;       ///< kAll: the parts; kForall, kWhen: the body (one)
  std::vector<PatternNode> vars;  ///< kForall
  /// kForall: the quantified nodes differ from each other and from the bound ones (our
  /// dialect's `forall` effects) rather than ranging over every node (AGM's).
  bool distinct = false;
  Formula condition;      ///< kWhen
  PatternEdge edge;       ///< kAddEdge, kRemoveEdge
  std::string var, type;  ///< kCreate (both), kDelete (var), kRetype (both)
  SourceLoc loc;
};

}  // namespace quiver::agents
