// quiver-agent: the commands of `quiver` that run for long on a robot — agent, gateway, echo,
// dump, and the DDS benchmarks' role processes (the hidden bench-dds-role) — in an executable
// that links only the replica, its store, DDS and security: no OpenCV, Graphviz, HTTP server,
// kinematics or planner files. `quiver agent ...` becomes this executable
// when it is beside it (tools/quiver.cc). Same options as in `quiver`.

#include <CLI/CLI.hpp>

#include "commands.h"
#include "huge_pages.h"

int main(int argc, char** argv) {
  quiver::tools::use_huge_pages(argv, true);  // its commands hold replicas; re-executing costs ~7 ms
  CLI::App app{"quiver-agent: a replicating agent, a team gateway, an observer (the same commands as in `quiver`)"};
  quiver::tools::add_global_options(app, "quiver-agent");
  quiver::tools::add_agent_commands(app);
  quiver::tools::add_echo_command(app);
  quiver::tools::add_gateway_command(app);
  quiver::tools::add_bench_role_command(app);
  quiver::tools::require_known_subcommands(app, "quiver-agent");
  return quiver::tools::run_cli(app, argc, argv);
}
