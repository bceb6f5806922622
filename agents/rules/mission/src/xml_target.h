#pragma once
// Private: AGM's XML targets (an <AGMModel> of symbols and links, as AGM's planner examples state
// them), read into a Mission.

#include <string_view>

#include "quiver/agents/rules/mission/mission.h"

namespace quiver::agents::inline rules::internal {

/// True when `text` is XML (its first character other than white space is '<').
bool looks_like_xml(std::string_view text);

/// Reads an AGM XML target: a symbol whose id is a number is a world node (a constant, the
/// number canonical: "05" is 5), any other id a variable; a link with enabled="false" must not
/// exist. Coordinates become the node's position; attributes and unknown elements are noted and
/// not matched (AGM's planner does not match them either).
/// @returns kMalformed naming "source:line:column: ..." and what is wrong.
Result<Mission> parse_xml_target(std::string_view text, std::string_view source);

}  // namespace quiver::agents::inline rules::internal
