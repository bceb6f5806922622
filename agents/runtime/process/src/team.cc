// A robot team file: its parsing and checks, and the team domain's DDS configuration.
#include "quiver/agents/runtime/process/team.h"

#include <arpa/inet.h>

#include <cctype>

#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

namespace quiver::agents::inline runtime {
namespace {

bool good_name(const std::string& s) {
  if (s.empty() || s.size() > 32) return false;
  for (char c : s)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_')) return false;
  return true;
}

// A unicast IPv4 address a host can have on a team network.
bool good_address(const std::string& s) {
  in_addr a{};
  if (inet_pton(AF_INET, s.c_str(), &a) != 1) return false;
  const std::uint32_t h = ntohl(a.s_addr);
  const std::uint32_t first = h >> 24;
  return h != 0 && first != 127 && first < 224 && h != 0xffffffffu;
}

}  // namespace

const TeamRobot* TeamFile::robot(const std::string& name) const {
  for (const TeamRobot& r : robots)
    if (r.name == name) return &r;
  return nullptr;
}

Result<TeamFile> parse_team_file(const std::string& text, const std::string& where) {
  auto bad = [&](const std::string& what) { return make_error(ErrorCode::kMalformed, where + ": " + what); };
  nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
  if (j.is_discarded() || !j.is_object()) return bad("not a JSON object (a team file: docs/teams.md)");
  TeamFile t;
  if (!j.contains("team") || !j["team"].is_string() || !good_name(j["team"].get<std::string>()))
    return bad("\"team\" must be a name of 1 to 32 letters, digits, '-' or '_'");
  t.team = j["team"].get<std::string>();
  if (j.contains("domain")) {
    if (!j["domain"].is_number_unsigned() || j["domain"].get<std::uint64_t>() > 230)
      return bad("\"domain\" must be a DDS domain id from 0 to 230");
    t.domain = j["domain"].get<std::uint32_t>();
  }
  if (j.contains("lease_s")) {
    if (!j["lease_s"].is_number() || j["lease_s"].get<double>() < 0.1 || j["lease_s"].get<double>() > 3600)
      return bad("\"lease_s\" must be a number of seconds from 0.1 to 3600");
    t.lease_s = j["lease_s"].get<double>();
  }
  if (!j.contains("robots") || !j["robots"].is_array() || j["robots"].empty())
    return bad("\"robots\" must be a non-empty array of {\"name\", \"address\"}");
  std::set<std::string> names, addresses;
  for (std::size_t i = 0; i < j["robots"].size(); ++i) {
    const auto& r = j["robots"][i];
    const std::string at = "robots[" + std::to_string(i) + "]";
    if (!r.is_object() || !r.contains("name") || !r["name"].is_string() || !good_name(r["name"].get<std::string>()))
      return bad(at + ".name must be a name of 1 to 32 letters, digits, '-' or '_'");
    if (!r.contains("address") || !r["address"].is_string() || !good_address(r["address"].get<std::string>()))
      return bad(at + ".address must be a unicast IPv4 address (not loopback, multicast, broadcast or 0.0.0.0)");
    TeamRobot robot{r["name"].get<std::string>(), r["address"].get<std::string>()};
    if (!names.insert(robot.name).second) return bad(at + ": robot name '" + robot.name + "' given twice");
    if (!addresses.insert(robot.address).second) return bad(at + ": address " + robot.address + " given twice");
    t.robots.push_back(std::move(robot));
  }
  return t;
}

Result<TeamFile> load_team_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) return make_error(ErrorCode::kIo, "team file '" + path + "': cannot be read");
  std::ostringstream ss;
  ss << in.rdbuf();
  return parse_team_file(ss.str(), "team file '" + path + "'");
}

Result<DdsConfig> team_dds_config(const TeamFile& team, const std::string& robot, DdsConfig base) {
  const TeamRobot* self = team.robot(robot);
  if (self == nullptr) return make_error(ErrorCode::kNotFound, "robot '" + robot + "' is not in team '" + team.team + "'");
  NetworkDomain net;
  net.address = self->address;
  for (const TeamRobot& r : team.robots) net.peers.push_back(r.address);
  net.tag = "quiver-team-" + team.team;
  base.domain = team.domain;
  base.lease_ns = static_cast<std::int64_t>(team.lease_s * 1e9);
  base.source = DdsConfig::Source::kXml;
  base.xml = network_config_xml(net, base);
  return base;
}

}  // namespace quiver::agents
