#pragma once
// What each quiver subcommand file adds to the command line (add_*_commands).

#include <CLI/CLI.hpp>

#include <string>

namespace quiver::tools {

struct ExtraRoles;

/// Every subcommand of `quiver`, with its options and checks.
void build_app(CLI::App& app);
/// The options every quiver executable has: --version (naming `program`) and --log-level.
void add_global_options(CLI::App& app, const std::string& program);
/// Once the commands are added: a missing or unknown command word gets an error naming the
/// known ones.
void require_known_subcommands(CLI::App& app, const std::string& program);
/// Parses the command line and runs the chosen command: the process exit status.
int run_cli(CLI::App& app, int argc, char** argv);

void add_sim_command(CLI::App& app);
void add_bench_commands(CLI::App& app);
/// lookup, import-urdf, bench transforms, bench scene (needs add_bench_commands first).
void add_kinematics_commands(CLI::App& app);
/// agent (a replicating agent process), dump (an observer that prints the graph).
void add_agent_commands(CLI::App& app);
/// echo (the graph's changes on a live domain, as they arrive).
void add_echo_command(CLI::App& app);
/// launch (a set of agents from a launch file, stopped together).
void add_launch_command(CLI::App& app);
/// gateway (a robot team).
void add_gateway_command(CLI::App& app);
void add_dds_bench_commands(CLI::App& app);
/// bench-dds-role (hidden: one process of a DDS benchmark; in quiver-agent and quiver).
void add_bench_role_command(CLI::App& app);
void add_agents_bench_commands(CLI::App& app);
/// run ROLE (the Barthel roles and `extra`'s), scenario barthel.
void add_barthel_commands(CLI::App& app, const ExtraRoles& extra);
/// The AGM scenarios' roles, for `run ROLE`.
ExtraRoles agm_roles();
/// scenario agm, bench humans (needs add_bench_commands and add_barthel_commands first).
void add_agm_commands(CLI::App& app);
/// render (a picture of a world, a recording's state or a live domain), timeline (a recording's
/// evolution as PNG frames or an MP4).
void add_render_commands(CLI::App& app);
/// bench reaction (needs add_bench_commands first).
void add_reaction_bench_command(CLI::App& app);
/// bench store (needs add_bench_commands first).
void add_store_bench_command(CLI::App& app);
/// view, record.
void add_view_commands(CLI::App& app);
/// import-dsr, import-agm, export-dsr, export-agm.
void add_interop_commands(CLI::App& app);
/// grammar check.
void add_grammar_commands(CLI::App& app);
/// mission check, plan, bench planner (needs add_bench_commands first).
void add_planner_commands(CLI::App& app);
/// schema infer, schema check (the shared vocabulary).
void add_schema_commands(CLI::App& app);
/// keys init, keys add-agent, keys revoke, keys list (DDS Security credentials).
void add_keys_commands(CLI::App& app);
/// The process exit status the command that ran has chosen.
int exit_code();
void set_exit_code(int code);

}  // namespace quiver::tools
