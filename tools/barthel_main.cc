// quiver-barthel: the Barthel test (seed 000) alone — scenario barthel, run ROLE for its five
// agents, bench reaction — in an executable that needs only the agent libraries, Cyclone DDS and
// OpenCV's core and PNG codec (the Panel's screen): what `./run.sh demo` builds. `quiver scenario
// barthel` starts its agents with this executable when it is beside it.

#include <CLI/CLI.hpp>

#include <cstring>

#include "commands.h"
#include "huge_pages.h"
#include "run_flags.h"

int main(int argc, char** argv) {
  quiver::tools::use_huge_pages(argv, argc > 1 && std::strcmp(argv[1], "run") == 0);  // an agent role
  CLI::App app{"quiver-barthel: the Barthel test by agent processes over DDS (the same commands as in `quiver`)"};
  quiver::tools::add_global_options(app, "quiver-barthel");
  app.add_subcommand("bench", "Benchmarks (one JSON line per result)");
  quiver::tools::add_barthel_commands(app, quiver::tools::ExtraRoles{});
  quiver::tools::add_reaction_bench_command(app);
  quiver::tools::require_known_subcommands(app, "quiver-barthel");
  return quiver::tools::run_cli(app, argc, argv);
}
