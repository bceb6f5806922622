#pragma once
// AGM's PDDL-like formulas: `precondition { ... }` into a Formula the checker evaluates,
// `effect { ... }` into an Effect it applies (docs/grammar.md, "AGM's dialect").

#include <functional>
#include <set>
#include <string>

#include "grammar_lexer.h"
#include "quiver/agents/rules/grammar/grammar.h"

namespace quiver::agents::inline rules::internal {

/// Parses one s-expression precondition at the cursor (it must start with '('). `scope` holds
/// the variables it may name (the rule's left-hand side and parameters); a variable unknown
/// there, or to a quantifier around it, is an error. `(forall V (when C F))` becomes
/// `forall V { C } => { F }` and `(forall V (not E))` becomes `not exists V { E }`, so that the
/// checker anchors their variables on the edges of C and E.
/// `use_type` is told every type a quantifier or `create` names (the parser declares it or
/// refuses it).
using TypeUse = std::function<void(const Token& type)>;
Formula parse_agm_precondition(TokenCursor& in, const std::set<std::string>& scope,
                               const TypeUse& use_type);

/// Parses one s-expression effect at the cursor. `scope`: the rule's variables of both sides;
/// `create` adds its variable to the scope of what follows it.
Effect parse_agm_effect(TokenCursor& in, const std::set<std::string>& scope,
                        const TypeUse& use_type);

}  // namespace quiver::agents::inline rules::internal
