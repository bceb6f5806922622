#pragma once
/// @file
/// The files the Barthel agents ship with, embedded so that `quiver run ROLE` works anywhere:
/// each agent's grammar (agents/apps/barthel/grammars/ROLE.aggl) and the world (world/barthel.json).
#include <string_view>

namespace quiver::agents::inline apps::barthel {

/// The grammar of `role` (planner, speech, panel, person, patient); empty if there is none.
std::string_view role_grammar(std::string_view role);
/// The Barthel world file (JSON).
std::string_view world_json();
/// An embedded file by its name ("speech.aggl", "barthel.json"); empty if there is none.
std::string_view embedded_file(std::string_view name);

}  // namespace quiver::agents::inline apps::barthel
