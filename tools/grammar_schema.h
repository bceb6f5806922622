#pragma once
// A grammar against the shared vocabulary: what its rules use that a schema does not declare
// (`quiver grammar check --schema`, `quiver schema check`), and the vocabulary it implies
// (`quiver schema infer`).

#include <string>
#include <vector>

#include "quiver/agents/rules/grammar/grammar.h"
#include "quiver/agents/rules/schema/schema.h"

namespace quiver::tools {

/// One line per use the schema does not allow: a node type it does not declare, an edge label
/// that is no edge type of it, or an edge whose ends' types it never lets that edge join; each
/// names the rule (or constraint), its file and line.
/// The same for one pattern (a rule's side, a mission), appended to `out` once each; `where`
/// names it.
void pattern_schema_errors(const agents::Pattern& p, const agents::schema::Schema& s, const std::string& where,
                           std::vector<std::string>& out);
std::vector<std::string> grammar_schema_errors(const agents::Grammar& g, const agents::schema::Schema& s);
/// Adds the grammar's node types (with their bases) and its edge labels (with the node types seen
/// at their ends) to `s`.
void infer_from_grammar(const agents::Grammar& g, agents::schema::Schema& s);

}  // namespace quiver::tools
