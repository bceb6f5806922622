// quiver-plan: the planner's commands alone (mission check, plan, bench planner) in a small
// executable. The full `quiver` links OpenCV, Graphviz, Cyclone DDS and more, whose loading and
// initialisers take ~0.2 s before main(); this one starts in milliseconds, so that a planning
// request from a script costs what planning costs. Same options as `quiver plan` etc.

#include <CLI/CLI.hpp>

#include "commands.h"

int main(int argc, char** argv) {
  CLI::App app{"quiver-plan: missions and the planner (docs/planner.md); the same commands as in `quiver`"};
  app.add_subcommand("bench", "Benchmarks (one JSON line per result)");
  quiver::tools::add_planner_commands(app);
  app.require_subcommand(1);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  return quiver::tools::exit_code();
}
