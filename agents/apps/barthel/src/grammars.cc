// The Barthel agents' embedded files by role: each role's grammar and the world file.
#include "quiver/agents/apps/barthel/grammars.h"

#include <string>

namespace quiver::agents::inline apps::barthel {

std::string_view role_grammar(std::string_view role) { return embedded_file(std::string(role) + ".aggl"); }

std::string_view world_json() { return embedded_file("barthel.json"); }

}  // namespace quiver::agents::inline apps::barthel
