#pragma once
// Command-line options shared by every command that joins a DDS domain.

#include <CLI/CLI.hpp>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>

#include "quiver/agents/runtime/process/dds_replica.h"
#include "quiver/agents/transport/dds/dds_transport.h"
#include "quiver/agents/runtime/process/security_setup.h"
#include "quiver/agents/runtime/process/process_host.h"
#include "quiver/base/result.h"

namespace quiver::tools {

/// The DDS flags of the agent process host, for commands that open a replica themselves.
struct DdsFlags : agents::ProcessFlags {
  /// With `security`: also sign deltas and check the graph-level permissions. Benchmarks turn it
  /// off to measure what DDS Security alone costs.
  bool graph_security = true;
  void add_to(CLI::App* cmd) { add_dds(cmd); }
  /// A replica on the chosen domain and configuration; the other options come from `o`.
  Result<std::unique_ptr<agents::DdsReplica>> create_agent(agents::DdsReplicaOptions o) const {
    if (Status s = check(); !s.ok()) return s.error();
    if (Status s = apply_to(o.dds); !s.ok()) return s.error();
    apply_to(o.replicator);
    if (!security.empty())
      if (Status s = agents::enable_security(o, security); !s.ok()) return make_error(s.error().code, "--security: " + s.error().message);
    if (!graph_security) o.permissions = nullptr;
    if (Status s = apply_schema(o); !s.ok()) return s.error();
    return agents::DdsReplica::create(o);
  }
};

}  // namespace quiver::tools
