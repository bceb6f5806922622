#pragma once
// The two grammar parsers behind parse_grammar() and load_grammar_file() (grammar_load.cc).

#include <functional>
#include <string>
#include <string_view>

#include "quiver/agents/rules/grammar/grammar.h"

namespace quiver::agents::inline rules::internal {

/// Our dialect (grammar_parse.cc).
Result<Grammar> parse_quiver_grammar(std::string_view text, std::string_view source);

/// Reads the grammar an include(PATH) names (written at `at` of the including file).
using IncludeFn = std::function<Result<Grammar>(const std::string& path, SourceLoc at)>;

/// AGM's dialect (aggl_agm_parse.cc). Without `include`, an include(...) is an error.
Result<Grammar> parse_agm_grammar(std::string_view text, std::string_view source,
                                  const IncludeFn& include);

}  // namespace quiver::agents::inline rules::internal
