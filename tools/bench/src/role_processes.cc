// The role processes of the DDS benchmarks: their command lines, and their JSON result lines.
#include "quiver/tools/bench/role_processes.h"

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
  argv.insert(argv.end(), extra.begin(), extra.end());
  return argv;
}

std::optional<std::vector<Subprocess>> spawn_roles(const RoleCommand& c, const std::string& role,
                                                   int n, const std::vector<std::string>& common) {
  std::vector<Subprocess> out;
  for (int i = 0; i < n; ++i) {
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
      agents::named_logger("quiver bench dds")->error("no result from the {} process", who);
      return std::nullopt;
    }
    auto j = json::parse(*line, nullptr, false);
    if (!j.is_discarded() && j.is_object()) return j;
  }
}

}  // namespace quiver::tools::bench
