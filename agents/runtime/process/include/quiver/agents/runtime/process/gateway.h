#pragma once
/// @file
/// A robot's gateway to its team (docs/teams.md): one process holding two full replicas, one in
/// the robot's own domain (its agents' loopback domain) and one in the team domain on the team
/// network (team.h), joined by a ReplicaBridge, so that every change made on any robot reaches
/// every agent of every robot while the traffic between robots grows with the robots, not with
/// their agents. When the team network fails the robot keeps working alone; when it returns, the
/// gateways compare and exchange what they missed.
///
/// One thread runs both replicas and the bridge. Errors are returned or logged; nothing throws.

#include <string>

#include "quiver/agents/runtime/process/process_host.h"  // and CLI::App, by name only

namespace quiver::agents::inline runtime {

struct GatewayFlags {
  /// The robot side: --domain, --dds-config, --loss-permille, --lease, --membership, --security,
  /// and --status-ms, --run-for, --hand-over, --store (DIR/robot and DIR/team), --durability.
  ProcessFlags robot_side;
  std::string robot;      ///< this robot's name in the team file
  std::string team_file;  ///< team.h
  std::string name;       ///< the gateway's agent name (default ROBOT-gateway); its team replica adds ".team"
  /// DDS Security on the team domain: a `quiver keys` directory of the team's CA holding the
  /// credentials of NAME.team (authentication, encryption and access control; the graph-level
  /// permissions of --security stay on the robot side). Empty: an unsecured team domain.
  std::string team_security;
  int team_loss_permille = 0;     ///< testing: Cyclone drops this share of what the team replica sends
  bool print_team_config = false;  ///< print the team domain's Cyclone XML and exit
  /// Adds the flags to `cmd`. @pre this object outlives the parse.
  void add(CLI::App* cmd);
};

/// Runs a gateway until SIGINT/SIGTERM or --run-for; prints a JSON status line every
/// --status-ms (and one at the end): the digests of both replicas, their peers, what crossed.
/// @returns 0, or 2 when it could not start (a bad team file, an unknown robot, the team domain
///          equal to the robot's, a DDS error; the reason on stderr).
int run_gateway(const GatewayFlags& flags);

}  // namespace quiver::agents
