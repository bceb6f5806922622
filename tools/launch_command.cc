// quiver launch FILE: starts the agents a launch file names (processes, their options, a restart
// policy each, logs in one folder) and stops them all cleanly together; what `ros2 launch` is for
// ROS 2 nodes. The file is JSON (docs/agents.md, "Launching a set of agents").
#include <signal.h>
#include <unistd.h>

#include <filesystem>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "commands.h"
#include "quiver/agents/runtime/process/launcher.h"
#include "quiver/agents/runtime/process/logging.h"
#include "quiver/agents/runtime/process/process_host.h"

namespace quiver::tools {
namespace {

using nlohmann::json;

struct LaunchFlags {
  std::string file;
  std::string logs;  ///< overrides the file's
  double for_s = 0;  ///< stop all after this long (0: on Ctrl-C or when all have ended)
  bool check = false;  ///< only read the file and print what it would start
};

const char* restart_name(agents::Restart r) {
  switch (r) {
    case agents::Restart::kNever: return "never";
    case agents::Restart::kOnFailure: return "on-failure";
    case agents::Restart::kAlways: return "always";
  }
  return "?";
}

// --check: the file read as the launcher reads it, one line per agent; nothing started.
void print_plan(const agents::LaunchFile& file) {
  for (const agents::LaunchAgent& a : file.agents) {
    std::cout << a.name << ": " << (a.command.empty() ? "quiver" : a.command);
    for (const std::string& arg : a.args) std::cout << " " << arg;
    std::cout << "  (restart " << restart_name(a.restart);
    if (a.start_after_s > 0) std::cout << ", after " << a.start_after_s << " s";
    std::cout << ")\n";
  }
}

int run_launch(const LaunchFlags& flags) {
  auto log = agents::named_logger("quiver launch");
  auto file = agents::load_launch_file(flags.file);
  if (!file.ok()) {
    log->error("{}", file.error().message);
    return 2;
  }
  if (flags.check) {
    print_plan(*file);
    return 0;
  }
  namespace fs = std::filesystem;
  const fs::path logs = !flags.logs.empty() ? fs::path(flags.logs)
                        : !file->logs.empty() ? fs::path(flags.file).parent_path() / file->logs
                                              : fs::path("quiver-launch-logs");
  std::error_code ec;
  fs::create_directories(logs, ec);
  if (ec) {
    log->error("cannot make the logs' folder {}: {}", logs.string(), ec.message());
    return 2;
  }
  agents::Launcher launcher(logs.string());
  launcher.on_note([&](bool warn, const std::string& s) { warn ? log->warn("{}", s) : log->info("{}", s); });
  log->info("{} agents from {}; logs in {} (Ctrl-C stops them all)", file->agents.size(), flags.file, logs.string());
  agents::stop_on_signals();
  for (const agents::LaunchAgent& a : file->agents) (void)launcher.start(a);
  const std::int64_t t0 = agents::monotonic_ns();
  const std::int64_t deadline = flags.for_s > 0 ? t0 + static_cast<std::int64_t>(flags.for_s * 1e9) : 0;
  while (!agents::stop_requested() && (deadline == 0 || agents::monotonic_ns() < deadline) &&
         (launcher.running() > 0 || launcher.pending() > 0)) {
    launcher.poll();
    ::usleep(50'000);
  }
  // One clean stop for all: SIGTERM (each agent hands over and leaves), then SIGKILL after the grace.
  if (launcher.running() > 0) log->info("stopping {} agents", launcher.running());
  launcher.stop_all(file->stop_grace_s);
  json out;
  out["launch"] = flags.file;
  out["logs"] = logs.string();
  bool ok = true;
  for (const auto& [name, r] : launcher.records()) {
    out["agents"][name] = {{"starts", r.starts}, {"last_status", r.last_status}};
    // Stopped by us (SIGTERM: the agent's clean stop returns 0) or ended well.
    ok = ok && !r.failed_to_start && (r.last_status == 0 || r.last_status == 128 + SIGTERM) && r.starts > 0;
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
  launch->add_flag("--check", f->check, "only read the file and print the agents it would start (exit 2 if malformed)");
  launch->callback([f] { set_exit_code(run_launch(*f)); });
}

}  // namespace quiver::tools
