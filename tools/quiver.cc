// The quiver command: simulations, agents, inspection and benchmarks.

#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <string>

#include "commands.h"
#include "huge_pages.h"
#include "quiver/agents/runtime/process/subprocess.h"

namespace {

// The commands that a lean executable beside this one has too (tools/agent_main.cc): a process
// that runs one for long (an agent, a gateway, an observer) becomes that executable, so that it
// does not map OpenCV, Graphviz, the HTTP server and the rest of this one (docs/performance.md,
// "Lean agent processes"). Where it is missing, or with QUIVER_IN_ONE_EXECUTABLE=1 (the baseline
// of `quiver bench footprint`), the command runs here.
void become_lean_executable(int argc, char** argv) {
  if (argc < 2) return;
  if (const char* one = std::getenv("QUIVER_IN_ONE_EXECUTABLE"); one && std::strcmp(one, "1") == 0) return;
  for (const char* command : {"agent", "gateway", "echo", "dump"}) {
    if (std::strcmp(argv[1], command) != 0) continue;
    const std::optional<std::string> lean = quiver::agents::sibling_executable("quiver-agent");
    if (!lean) return;
    char* const self = argv[0];
    argv[0] = const_cast<char*>(lean->c_str());
    execv(lean->c_str(), argv);
    argv[0] = self;  // not executable after all: run it here
    return;
  }
}

}  // namespace

int main(int argc, char** argv) {
  become_lean_executable(argc, argv);
  // Re-executing the whole CLI costs about as much as starting it (0.24 s): only for the commands
  // that hold a replica for long (`agent` and its kin usually became quiver-agent just above).
  bool replica = false;
  for (const char* command : {"bench-dds-role", "view", "run", "agent", "gateway", "echo", "dump"})
    replica = replica || (argc > 1 && std::strcmp(argv[1], command) == 0);
  quiver::tools::use_huge_pages(argv, replica);
  CLI::App app{"quiver: a replicated world model for robot agents (no executive, delta CRDTs over DDS)"};
  quiver::tools::build_app(app);
  return quiver::tools::run_cli(app, argc, argv);
}
