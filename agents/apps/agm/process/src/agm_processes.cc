// The AGM agents as OS processes: started, killed, restarted and stopped by role.
#include "quiver/agents/apps/agm/process/agm_processes.h"

#include <csignal>
#include <cstdlib>

namespace quiver::agents::inline apps::agm {

AgmProcesses::AgmProcesses(AgmProcessOptions o) : o_(std::move(o)), launcher_(o_.out + "/logs", o_.exe) {}

AgmProcesses::~AgmProcesses() { launcher_.stop_all(5); }

bool AgmProcesses::start(const std::string& role, std::vector<std::string> extra) {
  LaunchAgent a;
  a.name = role;
  a.args = {"run", role, "--domain", std::to_string(o_.dds.domain), "--dds-config", o_.dds.dds_config, "--join-wait", "1"};
  a.args.insert(a.args.end(), extra.begin(), extra.end());
  if (!launcher_.start(std::move(a)).ok()) return false;
  args_[role] = std::move(extra);
  return true;
}

int AgmProcesses::kill(const std::string& role) { return launcher_.kill(role, SIGKILL); }

std::optional<nlohmann::json> AgmProcesses::stop(const std::string& role) { return launcher_.stop(role, 5); }

}  // namespace quiver::agents::inline apps::agm
