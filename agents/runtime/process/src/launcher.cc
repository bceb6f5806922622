// A set of agent processes started and supervised together: spawned with their logs, reaped,
// restarted as their policy says, stopped cleanly together.
#include "quiver/agents/runtime/process/launcher.h"

#include <sys/stat.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <thread>

#include "quiver/agents/runtime/process/dds_replica.h"

namespace quiver::agents::inline runtime {

struct Launcher::Agent {
  LaunchAgent spec;
  std::optional<Subprocess> proc;  // while it runs
  Record record;
  std::int64_t start_at = -1;  // when to start (again); -1: not
  std::optional<nlohmann::json> last;
  std::ofstream log;
};

namespace {
std::string ended(int status) {
  return status >= 128 ? "signal " + std::to_string(status - 128) : "exit " + std::to_string(status);
}
}  // namespace

Launcher::Launcher(std::string logs, std::string self) : logs_(std::move(logs)), self_(std::move(self)) {
  std::error_code ec;
  std::filesystem::create_directories(logs_, ec);
}

Launcher::~Launcher() {
  for (auto& [name, a] : agents_)
    if (a->proc) {
      a->proc->kill(SIGKILL);
      a->proc->wait(2000);
    }
}

Status Launcher::start(LaunchAgent spec) {
  auto& slot = agents_[spec.name];
  if (slot && slot->proc) kill(spec.name, SIGKILL);
  if (!slot) slot = std::make_unique<Agent>();
  Agent& a = *slot;
  a.spec = std::move(spec);
  a.start_at = monotonic_ns() + static_cast<std::int64_t>(a.spec.start_after_s * 1e9);
  if (a.spec.start_after_s > 0) return {};
  return spawn(a);
}

Status Launcher::spawn(Agent& a) {
  const std::string path = logs_ + "/" + a.spec.name + ".log";
  if (!a.log.is_open()) a.log.open(path, std::ios::app);
  std::vector<std::string> argv{a.spec.command.empty() ? self_ : a.spec.command};
  argv.insert(argv.end(), a.spec.args.begin(), a.spec.args.end());
  SpawnOptions o;
  o.stderr_path = path;
  o.append = true;
  o.env.assign(a.spec.env.begin(), a.spec.env.end());
  o.own_group = true;  // a Ctrl-C at the terminal reaches the launcher, which stops each agent in turn
  o.search_path = !a.spec.command.empty();
  a.log.flush();
  int error = 0;
  a.proc = Subprocess::spawn(argv, o, &error);
  ++a.record.starts;
  a.start_at = -1;
  if (!a.proc) {
    a.record.failed_to_start = true;
    const std::string why = error != 0 ? std::strerror(error) : "no pipe";
    note(true, "cannot start " + a.spec.name + ": " + why);
    return make_error(ErrorCode::kIo, "cannot start agent '" + a.spec.name + "' (" + argv[0] + "): " + why);
  }
  note(false, "started " + a.spec.name + " (pid " + std::to_string(a.proc->pid()) +
                  (a.record.starts > 1 ? ", start " + std::to_string(a.record.starts) : std::string()) + ")");
  return {};
}

void Launcher::drain(Agent& a) {
  if (!a.proc) return;
  while (auto line = a.proc->read_line(0)) {
    a.log << *line << '\n';
    auto j = nlohmann::json::parse(*line, nullptr, false);
    if (j.is_object()) a.last = std::move(j);
  }
  a.log.flush();
}

void Launcher::reaped(Agent& a, int status, bool stopping) {
  drain(a);
  a.proc.reset();
  a.record.last_status = status;
  const bool failed = status != 0;
  const LaunchAgent& s = a.spec;
  const bool again = !stopping && (s.restart == Restart::kAlways || (s.restart == Restart::kOnFailure && failed)) &&
                     a.record.starts <= s.max_restarts;
  if (again) {
    a.start_at = monotonic_ns() + static_cast<std::int64_t>(s.restart_delay_s * 1e9);
    note(true, s.name + " ended (" + ended(status) + "): restarting in " + std::to_string(s.restart_delay_s) + " s (" +
                   std::to_string(a.record.starts) + " of " + std::to_string(s.max_restarts) + " restarts)");
  } else if (!stopping) {
    note(failed, s.name + " ended (" + ended(status) + ")" + (failed ? "; not restarted" : ""));
  }
}

void Launcher::poll() {
  const std::int64_t now = monotonic_ns();
  for (auto& [name, a] : agents_) {
    if (!a->proc && a->start_at >= 0 && now >= a->start_at && !stopping_) (void)spawn(*a);
    drain(*a);
    if (a->proc)
      if (const int st = a->proc->wait(0); st >= 0) reaped(*a, st, stopping_);
  }
}

int Launcher::running() const {
  int n = 0;
  for (const auto& [name, a] : agents_) n += a->proc ? 1 : 0;
  return n;
}

int Launcher::pending() const {
  int n = 0;
  for (const auto& [name, a] : agents_) n += !a->proc && a->start_at >= 0 ? 1 : 0;
  return n;
}

int Launcher::kill(const std::string& name, int sig) {
  auto it = agents_.find(name);
  if (it == agents_.end() || !it->second->proc) return -1;
  Agent& a = *it->second;
  const int pid = a.proc->pid();
  a.proc->kill(sig);
  if (sig == SIGKILL) {
    const int st = a.proc->wait(2000);
    drain(a);
    a.proc.reset();
    a.record.last_status = st;
    a.start_at = -1;
  }
  return pid;
}

std::optional<nlohmann::json> Launcher::stop(const std::string& name, double grace_s) {
  auto it = agents_.find(name);
  if (it == agents_.end()) return std::nullopt;
  Agent& a = *it->second;
  int status = a.record.last_status;
  if (a.proc) {
    a.proc->kill(SIGTERM);
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(grace_s);
    while ((status = a.proc->wait(0)) < 0 && std::chrono::steady_clock::now() < end) {
      drain(a);
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    if (status < 0) {
      a.proc->kill(SIGKILL);
      status = a.proc->wait(2000);
    }
    drain(a);
    a.proc.reset();
  }
  std::optional<nlohmann::json> last = std::move(a.last);
  if (last) (*last)["exit_status"] = status;
  agents_.erase(it);
  return last;
}

void Launcher::stop_all(double grace_s) {
  stopping_ = true;
  for (auto& [name, a] : agents_) {
    a->start_at = -1;
    if (a->proc) a->proc->kill(SIGTERM);
  }
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(grace_s);
  while (running() > 0 && std::chrono::steady_clock::now() < end) {
    poll();
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  for (auto& [name, a] : agents_)
    if (a->proc) {
      note(true, name + " did not stop within " + std::to_string(grace_s) + " s: killed");
      a->proc->kill(SIGKILL);
      reaped(*a, a->proc->wait(2000), true);
    }
  stopping_ = false;
}

std::optional<nlohmann::json> Launcher::last_status(const std::string& name) {
  auto it = agents_.find(name);
  if (it == agents_.end()) return std::nullopt;
  drain(*it->second);
  return it->second->last;
}

std::map<std::string, pid_t> Launcher::pids() const {
  std::map<std::string, pid_t> out;
  for (const auto& [name, a] : agents_) out[name] = a->proc ? a->proc->pid() : 0;
  return out;
}

std::map<std::string, Launcher::Record> Launcher::records() const {
  std::map<std::string, Record> out;
  for (const auto& [name, a] : agents_) out[name] = a->record;
  return out;
}

}  // namespace quiver::agents::inline runtime
