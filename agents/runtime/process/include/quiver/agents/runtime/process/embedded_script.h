#pragma once
/// @file
/// Running a bash script shipped inside the binary (`quiver bench team`, `quiver scenario team`:
/// their network-namespace choreography, with scripts/netns.sh), so that an installed `quiver`
/// has it too.
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace quiver::agents::inline runtime {

/// Writes `files` (name, text) into a fresh temporary directory, runs `bash DIR/script EXE args...`
/// (EXE: this executable's path), waits for it, and removes the directory. `who` prefixes what
/// goes wrong on stderr. @returns the script's exit status; 2 when it cannot be run.
int run_embedded_script(const std::string& who, const std::vector<std::pair<std::string, std::string_view>>& files,
                        const std::string& script, const std::vector<std::string>& args);

}  // namespace quiver::agents::inline runtime
