// quiver gateway: a robot's gateway to its team (docs/teams.md).

#include <memory>

#include "commands.h"
#include "quiver/agents/runtime/process/gateway.h"

namespace quiver::tools {

void add_gateway_command(CLI::App& app) {
  auto f = std::make_shared<agents::GatewayFlags>();
  auto* cmd = app.add_subcommand(
      "gateway", "Join this robot's agents to a robot team: a replica in the robot's domain and one in the team's "
                 "(a team file names the team network), bridged (docs/teams.md)");
  f->add(cmd);
  cmd->callback([f] { set_exit_code(agents::run_gateway(*f)); });
}

}  // namespace quiver::tools
