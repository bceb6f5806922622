#pragma once
// Command-line options shared by every command that joins a DDS domain.

#include <CLI/CLI.hpp>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>

#include "quiver/agents/dds/dds_replica.h"
#include "quiver/agents/dds/dds_transport.h"
#include "quiver/result.h"

namespace quiver::tools {

struct DdsFlags {
  std::uint32_t domain = 0;
  std::string config = "loopback";
  int loss_permille = 0;

  void add_to(CLI::App* cmd) {
    cmd->add_option("--domain", domain, "DDS domain id")->check(CLI::Range(0, 230))->capture_default_str();
    cmd->add_option("--dds-config", config,
                    "loopback (default: 127.0.0.1 only, multicast off), env (opt-in: use CYCLONEDDS_URI), "
                    "or the path of a Cyclone XML file (opt-in, e.g. for several hosts)")
        ->capture_default_str();
    cmd->add_option("--loss-permille", loss_permille, "testing: Cyclone drops this share of sent packets")
        ->check(CLI::Range(0, 999));
  }
  /// Sets the fields of `c` these flags choose (domain, configuration source, loss); leaves the
  /// rest.
  Status apply_to(agents::DdsConfig& c) const {
    c.domain = domain;
    c.xmit_loss_permille = loss_permille;
    if (config == "loopback") {
      c.source = agents::DdsConfig::Source::kLoopback;
    } else if (config == "env") {
      c.source = agents::DdsConfig::Source::kEnvironment;
    } else {
      std::ifstream in(config);
      if (!in) return make_error(ErrorCode::kIo, "--dds-config: cannot read '" + config + "'");
      std::ostringstream ss;
      ss << in.rdbuf();
      c.source = agents::DdsConfig::Source::kXml;
      c.xml = ss.str();
    }
    return {};
  }
  /// An agent on the chosen domain and configuration; the other options come from `o`.
  Result<std::unique_ptr<agents::DdsReplica>> create_agent(agents::DdsReplicaOptions o) const {
    if (Status s = apply_to(o.dds); !s.ok()) return s.error();
    return agents::DdsReplica::create(o);
  }
};

}  // namespace quiver::tools
