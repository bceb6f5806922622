#pragma once
/// @file
/// A robot team file (docs/teams.md): the explicit opt-in that joins robots into one world model.
/// It names the team, the DDS domain the robots' gateways meet in, and each robot's address on
/// the team network; discovery goes to those addresses only (unicast, no multicast).
///
/// ```json
/// {"team": "kitchen-crew", "domain": 7, "lease_s": 1,
///  "robots": [{"name": "A", "address": "10.77.0.1"}, {"name": "B", "address": "10.77.0.2"}]}
/// ```
///
/// Errors name the file, the field and what was wrong; nothing here throws.

#include <cstdint>
#include <string>
#include <vector>

#include "quiver/agents/transport/dds/dds_transport.h"
#include "quiver/base/result.h"

namespace quiver::agents::inline runtime {

struct TeamRobot {
  std::string name;     ///< [A-Za-z0-9_-]{1,32}, unique in the team
  std::string address;  ///< its IPv4 address on the team network, unique in the team
};

struct TeamFile {
  std::string team;          ///< the discovery tag: another team's participants never match
  std::uint32_t domain = 7;  ///< the team domain (not a robot's own domain)
  double lease_s = 1;        ///< the team domain's participant lease
  std::vector<TeamRobot> robots;
  /// @returns the robot named `name`, or null.
  const TeamRobot* robot(const std::string& name) const;
};

/// Parses a team file's text; `where` names it in errors.
/// @returns the team, or kMalformed naming the field: not JSON, a missing or mistyped field, a
///          robot name outside [A-Za-z0-9_-]{1,32}, an address that is not a unicast IPv4
///          address (loopback, multicast, broadcast and 0.0.0.0 are refused), a name or address
///          given twice, a domain outside 0..230, a lease outside 0.1..3600 s, no robot.
Result<TeamFile> parse_team_file(const std::string& text, const std::string& where);
/// Reads and parses a team file. @returns as parse_team_file(), or kIo if it cannot be read.
Result<TeamFile> load_team_file(const std::string& path);
/// The DDS configuration of robot `robot`'s gateway on the team domain: `base` (its name, role,
/// security) with the team's domain, lease and the network configuration (its address, every
/// robot's address as a peer, the team as discovery tag). @returns kNotFound for an unknown robot.
Result<DdsConfig> team_dds_config(const TeamFile& team, const std::string& robot, DdsConfig base);

}  // namespace quiver::agents
