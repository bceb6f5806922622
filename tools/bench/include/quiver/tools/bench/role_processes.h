#pragma once
// The role processes of the DDS benchmarks: `EXE bench-dds-role ROLE ...` started with the
// benchmark's DDS options, and the JSON line each prints as its result.

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "quiver/agents/runtime/process/process_host.h"
#include "quiver/agents/runtime/process/subprocess.h"

namespace quiver::tools::bench {

/// How a benchmark starts its role processes.
struct RoleCommand {
  /// The executable whose hidden `bench-dds-role ROLE` command runs a role (quiver-agent, the
  /// lean one, when it is there; run_dds_role() in dds_roles.h).
  std::string exe;
  /// The domain, DDS configuration, packet loss and security directory every role is given.
  agents::ProcessFlags dds;
  /// The executable whose `view` command attaches a viewer (the quiver command).
  std::string viewer_exe;
};

/// @returns the command line of one `role` process: the executable, `bench-dds-role ROLE`, the
/// DDS options of `c` (--domain, --dds-config, --loss-permille, and --security when set), then
/// `extra`.
std::vector<std::string> role_argv(const RoleCommand& c, const std::string& role,
                                   std::vector<std::string> extra);

/// Starts `n` processes of one `role`, numbered by --id 0..n-1, each with `common` arguments,
/// `gap_ms` apart.
/// @returns them, or nullopt when one cannot be started (those already started are then killed).
std::optional<std::vector<agents::Subprocess>> spawn_roles(const RoleCommand& c,
                                                           const std::string& role, int n,
                                                           const std::vector<std::string>& common,
                                                           int gap_ms = 0);

/// Reads `p`'s stdout until a line that is a JSON object, skipping any other line.
/// @returns that object, or nullopt (logged, naming the `who` process) when no line comes within
/// `timeout_ms` or the process ends first.
std::optional<nlohmann::json> read_json(agents::Subprocess& p, const char* who, int timeout_ms);

}  // namespace quiver::tools::bench
