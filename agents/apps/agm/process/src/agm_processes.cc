// The AGM agents as OS processes: started, killed, restarted and stopped by role.
#include "quiver/agents/apps/agm/process/agm_processes.h"

#include <sys/stat.h>

#include <csignal>
#include <cstdlib>

namespace quiver::agents::inline apps::agm {

AgmProcesses::AgmProcesses(AgmProcessOptions o) : o_(std::move(o)) {
  ::mkdir(o_.out.c_str(), 0755);
  ::mkdir((o_.out + "/logs").c_str(), 0755);
}

AgmProcesses::~AgmProcesses() {
  for (auto& [name, p] : procs_) p.kill(SIGTERM);
  for (auto& [name, p] : procs_) p.wait(5000);
}

bool AgmProcesses::start(const std::string& role, std::vector<std::string> extra) {
  std::vector<std::string> argv = {o_.exe,
                                   "run",
                                   role,
                                   "--domain",
                                   std::to_string(o_.dds.domain),
                                   "--dds-config",
                                   o_.dds.dds_config,
                                   "--join-wait",
                                   "1"};
  argv.insert(argv.end(), extra.begin(), extra.end());
  const int n = ++starts_[role];
  auto p = Subprocess::spawn(
      argv, o_.out + "/logs/" + role + (n > 1 ? "-" + std::to_string(n) : "") + ".log");
  if (!p) return false;
  args_[role] = extra;
  procs_.erase(role);
  procs_.emplace(role, std::move(*p));
  return true;
}

int AgmProcesses::kill(const std::string& role) {
  auto it = procs_.find(role);
  if (it == procs_.end()) return -1;
  it->second.kill(SIGKILL);
  it->second.wait(2000);
  return it->second.pid();
}

std::optional<nlohmann::json> AgmProcesses::stop(const std::string& role) {
  auto it = procs_.find(role);
  if (it == procs_.end()) return std::nullopt;
  it->second.kill(SIGTERM);
  std::optional<nlohmann::json> last;
  for (int i = 0; i < 100; ++i) {
    while (auto line = it->second.read_line(100)) {
      auto j = nlohmann::json::parse(*line, nullptr, false);
      if (j.is_object()) last = std::move(j);
    }
    if (last) break;
  }
  const int status = it->second.wait(5000);
  if (last) (*last)["exit_status"] = status;
  procs_.erase(it);
  return last;
}

}  // namespace quiver::agents::inline apps::agm
