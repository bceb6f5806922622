// The Barthel agents as one OS process each: starting, killing and restarting them by name.
#include "quiver/agents/apps/barthel/process/barthel_processes.h"

#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <csignal>

namespace quiver::agents::inline apps::barthel {
namespace {

// The agents' pids, for the signal handler: a scenario stopped by SIGINT or SIGTERM takes its
// agents with it instead of leaving them running on the domain.
constexpr int kMaxAgents = 32;
std::atomic<pid_t> g_agents[kMaxAgents];

extern "C" void stop_agents_and_exit(int sig) {
  for (auto& a : g_agents)
    if (pid_t p = a.load(); p > 0) ::kill(p, SIGTERM);
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

void remember(pid_t old_pid, pid_t new_pid) {
  for (auto& a : g_agents) {
    pid_t expected = old_pid;
    if (a.compare_exchange_strong(expected, new_pid)) return;
  }
}

}  // namespace

BarthelProcesses::BarthelProcesses(BarthelProcessOptions o) : o_(std::move(o)), launcher_(o_.out + "/logs", o_.exe) {
  ::mkdir(o_.out.c_str(), 0755);
  std::signal(SIGINT, stop_agents_and_exit);
  std::signal(SIGTERM, stop_agents_and_exit);
}

BarthelProcesses::~BarthelProcesses() { stop_all(); }

std::vector<std::string> BarthelProcesses::argv_of(const std::string& role, const std::string& name) const {
  std::vector<std::string> a = {"run",         role,          "--domain",    std::to_string(o_.domain),
                                "--dds-config", o_.dds_config, "--out",   o_.out,        "--script",
                                o_.script_path, "--join-wait", "1",       "--answer-timeout", std::to_string(o_.answer_timeout_s)};
  if (!name.empty()) a.insert(a.end(), {"--name", name});
  if (o_.simulated_speech) a.insert(a.end(), {"--simulated-speech", "--words-ms", std::to_string(o_.words_ms)});
  return a;
}

bool BarthelProcesses::start(const std::string& role, const std::string& name) {
  const std::string key = name.empty() ? role : name;
  LaunchAgent a;
  a.name = key;
  a.args = argv_of(role, name);  // this executable's `run ROLE`; restarted by the scenario, not by policy
  const pid_t old = launcher_.pids()[key];
  if (!launcher_.start(std::move(a)).ok()) return false;
  remember(old, 0);
  remember(0, launcher_.pids()[key]);
  return true;
}

int BarthelProcesses::kill(const std::string& name, int sig) { return launcher_.kill(name, sig); }

void BarthelProcesses::stop_all() {
  const auto pids = launcher_.pids();
  launcher_.stop_all(5);
  for (const auto& [name, pid] : pids) remember(pid, 0);
}

std::optional<nlohmann::json> BarthelProcesses::last_status(const std::string& name) {
  return launcher_.last_status(name);
}

}  // namespace quiver::agents::inline apps::barthel
