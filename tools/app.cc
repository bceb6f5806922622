// The quiver command: its subcommands collected from each *_commands.cc.
#include <CLI/CLI.hpp>

#include "commands.h"
#include "run_flags.h"

namespace quiver::tools {

void build_app(CLI::App& app) {
  add_global_options(app, "quiver");
  add_sim_command(app);
  add_bench_commands(app);
  add_kinematics_commands(app);  // adds to `bench`: after add_bench_commands
  add_interop_commands(app);
  add_agent_commands(app);
  add_echo_command(app);
  add_launch_command(app);
  add_gateway_command(app);
  add_dds_bench_commands(app);
  add_bench_role_command(app);
  add_agents_bench_commands(app);
  add_barthel_commands(app, agm_roles());
  add_agm_commands(app);  // adds to `scenario` and `bench`
  add_render_commands(app);
  add_reaction_bench_command(app);
  add_store_bench_command(app);
  add_view_commands(app);
  add_grammar_commands(app);
  add_planner_commands(app);
  add_keys_commands(app);
  add_schema_commands(app);
  require_known_subcommands(app, "quiver");
}

}  // namespace quiver::tools
