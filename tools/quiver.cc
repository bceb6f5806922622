// The quiver command: simulations, agents, inspection and benchmarks.

#include <CLI/CLI.hpp>

#include "commands.h"

int main(int argc, char** argv) {
  CLI::App app{"quiver: a replicated world model for robot agents (no executive, delta CRDTs over DDS)"};
  quiver::tools::build_app(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  return quiver::tools::exit_code();
}
