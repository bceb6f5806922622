#pragma once
// A combo rule as plain rules: the composition of its steps, so the checker matches it like
// any rule (anchored on the change) with no search over sequences.

#include <string>
#include <vector>

#include "quiver/agents/rules/grammar/grammar.h"

namespace quiver::agents::inline rules::internal {

/// The rules `combo` stands for: one per choice of its optional steps (every step in, first),
/// each the composition of its steps applied in order, variables the equivalences identify
/// being one node and the others distinct (`alias.var` names them, the first of a class naming
/// it). A choice whose steps contradict each other is left out. If a step has a precondition or
/// an effect, nothing is returned: their meaning depends on the intermediate states. `why`
/// says what was left out and why.
std::vector<Rule> compose_combo(const Grammar& g, const Rule& combo, std::vector<std::string>& why);

}  // namespace quiver::agents::inline rules::internal
