#include <CLI/CLI.hpp>

#include "commands.h"

namespace quiver::tools {

void build_app(CLI::App& app) {
  app.require_subcommand(1);
  add_sim_command(app);
  add_bench_commands(app);
  add_kinematics_commands(app);  // adds to `bench`: after add_bench_commands
  add_agent_commands(app);
  add_dds_bench_commands(app);
  add_agents_bench_commands(app);
  add_barthel_commands(app);
  add_reaction_bench_command(app);
}

}  // namespace quiver::tools
