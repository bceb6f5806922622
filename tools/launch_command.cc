// quiver launch FILE: starts the agents a launch file names (processes, their options, a restart
// policy each, logs in one folder) and stops them all cleanly together; what `ros2 launch` is for
// ROS 2 nodes. The file is JSON (docs/agents.md, "Launching a set of agents").
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <regex>
#include <string>
#include <vector>

#include "commands.h"
#include "quiver/agents/runtime/process/logging.h"
#include "quiver/agents/runtime/process/process_host.h"
#include "quiver/base/result.h"

extern char** environ;

namespace quiver::tools {
namespace {

using nlohmann::json;

enum class Restart { kNever, kOnFailure, kAlways };

struct LaunchAgent {
  std::string name;
  std::string command;             ///< empty: this quiver executable
  std::vector<std::string> args;
  std::map<std::string, std::string> env;
  Restart restart = Restart::kNever;
  int max_restarts = 5;
  double restart_delay_s = 1;
  double start_after_s = 0;
};

struct LaunchFile {
  std::vector<LaunchAgent> agents;
  std::string logs;  ///< the logs' folder (relative paths: to the file's folder)
  double stop_grace_s = 5;
};

Error bad(const std::string& file, const std::string& what) {
  return make_error(ErrorCode::kMalformed, "launch file '" + file + "': " + what);
}

Result<LaunchFile> load_launch_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) return make_error(ErrorCode::kIo, "launch file '" + path + "': cannot be read");
  json j;
  try {
    j = json::parse(in);
  } catch (const json::parse_error& e) {
    return bad(path, std::string("not JSON: ") + e.what());
  }
  if (!j.is_object()) return bad(path, "expected an object with \"agents\"");
  LaunchFile f;
  for (const auto& [key, v] : j.items()) {
    if (key == "agents") continue;
    if (key == "logs") {
      if (!v.is_string() || v.get<std::string>().empty()) return bad(path, "logs must be a folder's path");
      f.logs = v.get<std::string>();
    } else if (key == "stop_grace_s") {
      if (!v.is_number() || v.get<double>() < 0 || v.get<double>() > 600)
        return bad(path, "stop_grace_s must be a number of seconds from 0 to 600");
      f.stop_grace_s = v.get<double>();
    } else {
      return bad(path, "unknown field \"" + key + "\" (the fields are agents, logs, stop_grace_s)");
    }
  }
  if (!j.contains("agents") || !j["agents"].is_array() || j["agents"].empty())
    return bad(path, "agents must be a non-empty array");
  static const std::regex kName("[A-Za-z0-9_.-]{1,64}");
  for (std::size_t i = 0; i < j["agents"].size(); ++i) {
    const json& a = j["agents"][i];
    const std::string where = "agents[" + std::to_string(i) + "]";
    if (!a.is_object()) return bad(path, where + " must be an object");
    LaunchAgent la;
    for (const auto& [key, v] : a.items()) {
      if (key == "name") {
        if (!v.is_string() || !std::regex_match(v.get<std::string>(), kName))
          return bad(path, where + ".name must be 1 to 64 letters, digits, '_', '.' or '-' (it names the log file)");
        la.name = v.get<std::string>();
      } else if (key == "command") {
        if (!v.is_string() || v.get<std::string>().empty()) return bad(path, where + ".command must be a program");
        la.command = v.get<std::string>();
      } else if (key == "args") {
        if (!v.is_array()) return bad(path, where + ".args must be an array of strings");
        for (const json& x : v) {
          if (!x.is_string()) return bad(path, where + ".args must be an array of strings");
          la.args.push_back(x.get<std::string>());
        }
      } else if (key == "env") {
        if (!v.is_object()) return bad(path, where + ".env must be an object of strings");
        for (const auto& [k, x] : v.items()) {
          if (!x.is_string() || k.empty() || k.find('=') != std::string::npos)
            return bad(path, where + ".env must be an object of strings");
          la.env[k] = x.get<std::string>();
        }
      } else if (key == "restart") {
        const std::string r = v.is_string() ? v.get<std::string>() : "";
        if (r == "never") la.restart = Restart::kNever;
        else if (r == "on-failure") la.restart = Restart::kOnFailure;
        else if (r == "always") la.restart = Restart::kAlways;
        else return bad(path, where + ".restart must be never, on-failure or always");
      } else if (key == "max_restarts") {
        if (!v.is_number_integer() || v.get<int>() < 0) return bad(path, where + ".max_restarts must be a count");
        la.max_restarts = v.get<int>();
      } else if (key == "restart_delay_s" || key == "start_after_s") {
        if (!v.is_number() || v.get<double>() < 0 || v.get<double>() > 3600)
          return bad(path, where + "." + key + " must be a number of seconds from 0 to 3600");
        (key == "restart_delay_s" ? la.restart_delay_s : la.start_after_s) = v.get<double>();
      } else {
        return bad(path, where + ": unknown field \"" + key +
                             "\" (the fields are name, command, args, env, restart, max_restarts, restart_delay_s, "
                             "start_after_s)");
      }
    }
    if (la.name.empty()) return bad(path, where + " has no name");
    for (const LaunchAgent& other : f.agents)
      if (other.name == la.name) return bad(path, where + ": a second agent named '" + la.name + "'");
    if (la.command.empty() && la.args.empty()) return bad(path, where + " has neither command nor args");
    f.agents.push_back(std::move(la));
  }
  return f;
}

struct LaunchFlags {
  std::string file;
  std::string logs;  ///< overrides the file's
  double for_s = 0;  ///< stop all after this long (0: on Ctrl-C or when all have ended)
};

struct Running {
  const LaunchAgent* spec;
  pid_t pid = 0;             ///< 0: not running
  int starts = 0;
  int last_status = -1;      ///< the last exit status (128 + signal when killed)
  std::int64_t start_at = 0; ///< when to start (again); -1: never again
};

std::int64_t now_ns() { return agents::monotonic_ns(); }

pid_t spawn(const LaunchAgent& a, const std::string& self, const std::filesystem::path& log, std::string& why) {
  std::vector<std::string> args;
  args.push_back(a.command.empty() ? self : a.command);
  args.insert(args.end(), a.args.begin(), a.args.end());
  std::vector<char*> argv;
  for (auto& s : args) argv.push_back(s.data());
  argv.push_back(nullptr);
  std::vector<std::string> env;
  for (char** e = environ; *e != nullptr; ++e) {
    std::string kv = *e;
    if (!a.env.count(kv.substr(0, kv.find('=')))) env.push_back(std::move(kv));
  }
  for (const auto& [k, v] : a.env) env.push_back(k + "=" + v);
  std::vector<char*> envp;
  for (auto& s : env) envp.push_back(s.data());
  envp.push_back(nullptr);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, STDOUT_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
  posix_spawn_file_actions_adddup2(&fa, STDOUT_FILENO, STDERR_FILENO);
  posix_spawn_file_actions_addopen(&fa, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  // Its own process group: Ctrl-C reaches the launcher only, which stops every agent in turn.
  posix_spawnattr_t attr;
  posix_spawnattr_init(&attr);
  posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETPGROUP);
  posix_spawnattr_setpgroup(&attr, 0);
  pid_t pid = 0;
  const int err = a.command.empty() || a.command.find('/') != std::string::npos
                      ? posix_spawn(&pid, argv[0], &fa, &attr, argv.data(), envp.data())
                      : posix_spawnp(&pid, argv[0], &fa, &attr, argv.data(), envp.data());
  posix_spawn_file_actions_destroy(&fa);
  posix_spawnattr_destroy(&attr);
  if (err != 0) {
    why = std::strerror(err);
    return 0;
  }
  return pid;
}

int run_launch(const LaunchFlags& flags) {
  auto log = agents::named_logger("quiver launch");
  auto file = load_launch_file(flags.file);
  if (!file.ok()) {
    log->error("{}", file.error().message);
    return 2;
  }
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  fs::path logs = !flags.logs.empty() ? fs::path(flags.logs)
                  : !file->logs.empty() ? fs::path(flags.file).parent_path() / file->logs
                                        : fs::path("quiver-launch-logs");
  fs::create_directories(logs, ec);
  if (ec) {
    log->error("cannot make the logs' folder {}: {}", logs.string(), ec.message());
    return 2;
  }
  std::vector<Running> agents;
  const std::int64_t t0 = now_ns();
  for (const LaunchAgent& a : file->agents)
    agents.push_back(Running{&a, 0, 0, -1, t0 + static_cast<std::int64_t>(a.start_after_s * 1e9)});
  log->info("{} agents from {}; logs in {} (Ctrl-C stops them all)", agents.size(), flags.file, logs.string());
  agents::stop_on_signals();
  const std::int64_t deadline = flags.for_s > 0 ? t0 + static_cast<std::int64_t>(flags.for_s * 1e9) : 0;
  bool failed_to_start = false;
  auto running = [&] { return std::count_if(agents.begin(), agents.end(), [](const Running& r) { return r.pid != 0; }); };
  auto pending = [&] {
    return std::count_if(agents.begin(), agents.end(), [](const Running& r) { return r.pid == 0 && r.start_at >= 0; });
  };
  auto reap = [&](bool stopping) {
    for (;;) {
      int status = 0;
      const pid_t pid = ::waitpid(-1, &status, WNOHANG);
      if (pid <= 0) return;
      auto it = std::find_if(agents.begin(), agents.end(), [&](const Running& r) { return r.pid == pid; });
      if (it == agents.end()) continue;
      Running& r = *it;
      r.pid = 0;
      r.last_status = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
      const bool failed = r.last_status != 0;
      const LaunchAgent& a = *r.spec;
      const bool again = !stopping && (a.restart == Restart::kAlways || (a.restart == Restart::kOnFailure && failed)) &&
                         r.starts <= a.max_restarts;
      if (again) {
        r.start_at = now_ns() + static_cast<std::int64_t>(a.restart_delay_s * 1e9);
        log->warn("{} ended ({}): restarting in {} s ({} of {} restarts)", a.name,
                  WIFEXITED(status) ? "exit " + std::to_string(r.last_status) : "signal " + std::to_string(WTERMSIG(status)),
                  a.restart_delay_s, r.starts, a.max_restarts);
      } else {
        r.start_at = -1;
        if (!stopping)
          (failed ? log->warn("{} ended ({}); not restarted", a.name,
                              WIFEXITED(status) ? "exit " + std::to_string(r.last_status)
                                                : "signal " + std::to_string(WTERMSIG(status)))
                  : log->info("{} ended (exit 0)", a.name));
      }
    }
  };
  while (!agents::stop_requested() && (deadline == 0 || now_ns() < deadline) && (running() > 0 || pending() > 0)) {
    const std::int64_t now = now_ns();
    for (Running& r : agents) {
      if (r.pid != 0 || r.start_at < 0 || now < r.start_at) continue;
      std::string why;
      r.pid = spawn(*r.spec, self.string(), logs / (r.spec->name + ".log"), why);
      ++r.starts;
      if (r.pid == 0) {
        log->error("cannot start {}: {}", r.spec->name, why);
        r.start_at = -1;
        failed_to_start = true;
        continue;
      }
      log->info("started {} (pid {}{})", r.spec->name, r.pid,
                r.starts > 1 ? ", start " + std::to_string(r.starts) : std::string());
    }
    reap(false);
    ::usleep(50'000);
  }
  // One clean stop for all: SIGTERM (each agent hands over and leaves), then SIGKILL after the grace.
  if (running() > 0) {
    log->info("stopping {} agents", running());
    for (const Running& r : agents)
      if (r.pid != 0) ::kill(r.pid, SIGTERM);
    const std::int64_t grace_end = now_ns() + static_cast<std::int64_t>(file->stop_grace_s * 1e9);
    while (running() > 0 && now_ns() < grace_end) {
      reap(true);
      ::usleep(20'000);
    }
    for (const Running& r : agents)
      if (r.pid != 0) {
        log->warn("{} did not stop within {} s: killed", r.spec->name, file->stop_grace_s);
        ::kill(r.pid, SIGKILL);
      }
    while (running() > 0) {
      reap(true);
      ::usleep(10'000);
    }
  }
  json out;
  out["launch"] = flags.file;
  out["logs"] = logs.string();
  bool ok = !failed_to_start;
  for (const Running& r : agents) {
    out["agents"][r.spec->name] = {{"starts", r.starts}, {"last_status", r.last_status}};
    // Stopped by us (SIGTERM: the agent's clean stop returns 0) or ended well.
    ok = ok && (r.last_status == 0 || r.last_status == 128 + SIGTERM) && r.starts > 0;
  }
  out["ok"] = ok;
  std::cout << out.dump() << std::endl;
  return ok ? 0 : 1;
}

}  // namespace

void add_launch_command(CLI::App& app) {
  auto f = std::make_shared<LaunchFlags>();
  auto* launch = app.add_subcommand(
      "launch",
      "Start the agents a launch file names (their commands and options, a restart policy each, logs in one folder) "
      "and stop them all cleanly together on Ctrl-C (docs/agents.md)");
  launch->add_option("file", f->file, "the launch file (JSON)")->required()->check(CLI::ExistingFile);
  launch->add_option("--logs", f->logs, "the logs' folder (default: the file's \"logs\", else ./quiver-launch-logs)");
  launch->add_option("--for", f->for_s, "stop them all after this many seconds (0: on Ctrl-C, or when all have ended)")
      ->check(CLI::Range(0.0, 1e7));
  launch->callback([f] { set_exit_code(run_launch(*f)); });
}

}  // namespace quiver::tools
