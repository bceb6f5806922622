// The quiver command: simulations, agents, inspection and benchmarks.

#include <CLI/CLI.hpp>
#include <cstdio>
#include <iostream>

#include "commands.h"

int main(int argc, char** argv) {
  CLI::App app{"quiver: a replicated world model for robot agents (no executive, delta CRDTs over DDS)"};
  app.require_subcommand(1);
  quiver::tools::add_sim_command(app);
  quiver::tools::add_bench_commands(app);
  quiver::tools::add_kinematics_commands(app);  // adds to `bench`: after add_bench_commands
  quiver::tools::add_agent_commands(app);
  quiver::tools::add_dds_bench_commands(app);
  quiver::tools::add_agents_bench_commands(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  return quiver::tools::exit_code();
}
