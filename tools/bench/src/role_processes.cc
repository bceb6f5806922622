// The role processes of the DDS benchmarks: their command lines, and their JSON result lines.
#include "quiver/tools/bench/role_processes.h"

#include <chrono>
#include <thread>

#include "quiver/agents/runtime/process/logging.h"

namespace quiver::tools::bench {

using agents::Subprocess;
using json = nlohmann::json;

std::vector<std::string> role_argv(const RoleCommand& c, const std::string& role,
                                   std::vector<std::string> extra) {
  const agents::ProcessFlags& dds = c.dds;
  std::vector<std::string> argv = {
      c.exe,          "bench-dds-role",           role,
      "--domain",     std::to_string(dds.domain), "--dds-config",
      dds.dds_config, "--loss-permille",          std::to_string(dds.loss_permille)};
  if (!dds.security.empty()) argv.insert(argv.end(), {"--security", dds.security});
  argv.insert(argv.end(), {"--membership", dds.membership});
  if (dds.lease_s != agents::ProcessFlags{}.lease_s) argv.insert(argv.end(), {"--lease", std::to_string(dds.lease_s)});
  argv.insert(argv.end(), extra.begin(), extra.end());
  return argv;
}

std::optional<std::vector<Subprocess>> spawn_roles(const RoleCommand& c, const std::string& role,
                                                   int n, const std::vector<std::string>& common, int gap_ms) {
  std::vector<Subprocess> out;
  for (int i = 0; i < n; ++i) {
    if (i > 0 && gap_ms > 0) std::this_thread::sleep_for(std::chrono::milliseconds(gap_ms));
    auto extra = common;
    extra.insert(extra.end(), {"--id", std::to_string(i)});
    auto p = Subprocess::spawn(role_argv(c, role, extra));
    if (!p) return std::nullopt;
    out.push_back(std::move(*p));
  }
  return out;
}

std::optional<json> read_json(Subprocess& p, const char* who, int timeout_ms) {
  for (;;) {
    auto line = p.read_line(timeout_ms);
    if (!line) {
      // Why: still running (a timeout), or how it ended (a signal shows as 128 + its number).
      const int status = p.wait(100);
      const std::string how = status < 0    ? "still running after the wait"
                              : status > 128 ? "killed by signal " + std::to_string(status - 128)
                                             : "exited with status " + std::to_string(status);
      agents::named_logger("quiver bench dds")->error("no result from the {} process (pid {}): {}", who, p.pid(), how);
      return std::nullopt;
    }
    auto j = json::parse(*line, nullptr, false);
    if (!j.is_discarded() && j.is_object()) return j;
  }
}

}  // namespace quiver::tools::bench
