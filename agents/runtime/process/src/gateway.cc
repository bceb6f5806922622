// A robot's gateway to its team: a replica in the robot's domain and one in the team's, bridged.
#include "quiver/agents/runtime/process/gateway.h"

#include <CLI/CLI.hpp>

#include <iostream>
#include <nlohmann/json.hpp>

#include "quiver/agents/replica/replication/bridge.h"
#include "quiver/agents/replica/security/keys.h"
#include "quiver/agents/runtime/process/logging.h"
#include "quiver/agents/runtime/process/replica_reports.h"
#include "quiver/agents/runtime/process/team.h"

namespace quiver::agents::inline runtime {
namespace {

// Each replica waits this long for traffic per turn: a change crosses within about two turns.
constexpr std::int64_t kTurnNs = 1'000'000;

nlohmann::json status(const std::string& name, DdsReplica& robot, DdsReplica& team, const ReplicaBridge& bridge) {
  const auto& rs = robot.replicator().stats();
  const auto& ts = team.replicator().stats();
  nlohmann::json j;
  j["name"] = name;
  j["digest"] = robot.graph().digest().hex();
  j["team_digest"] = team.graph().digest().hex();
  j["nodes"] = robot.graph().node_count();
  j["peers"] = robot.replicator().live_peer_count();
  j["team_peers"] = team.replicator().live_peer_count();
  j["synced"] = robot.replicator().synced();
  j["team_synced"] = team.replicator().synced();
  j["even"] = bridge.even();  // both replicas hold the same (origin, seq) set
  j["deltas_to_team"] = bridge.stats().deltas_to[1];
  j["deltas_to_robot"] = bridge.stats().deltas_to[0];
  j["states_to_team"] = bridge.stats().states_to[1];
  j["states_to_robot"] = bridge.stats().states_to[0];
  j["rejected"] = rs.rejected + ts.rejected;
  j["equivocations"] = rs.equivocations + ts.equivocations;
  j["divergences"] = rs.divergences + ts.divergences;
  j["team_write_timeouts"] = team.transport().stats().write_timeouts;
  j["rss_kb"] = resident_kb();
  j["t_ms"] = monotonic_ns() / 1'000'000;
  return j;
}

}  // namespace

void GatewayFlags::add(CLI::App* cmd) {
  cmd->add_option("--robot", robot, "this robot's name in the team file")->required();
  cmd->add_option("--team", team_file, "the team file (docs/teams.md): the team domain and every robot's address")
      ->required();
  cmd->add_option("--name", name, "the gateway's agent name (default ROBOT-gateway; its team replica adds .team)");
  robot_side.add_dds(cmd);
  cmd->add_option("--team-security", team_security,
                  "DDS Security on the team domain: the team CA's `quiver keys` directory, with credentials for "
                  "NAME.team; hosts without them read and write nothing there (docs/teams.md)");
  cmd->add_option("--team-loss-permille", team_loss_permille,
                  "testing: Cyclone drops this share of the packets the team replica sends")
      ->check(CLI::Range(0, 999));
  cmd->add_option("--status-ms", robot_side.status_ms, "print a JSON status line this often")
      ->check(CLI::Range(0, 3'600'000));
  cmd->add_option("--run-for", robot_side.run_for_s, "exit after this many seconds (default 0: until SIGINT/SIGTERM)")
      ->check(CLI::Range(0.0, 1e7));
  cmd->add_option("--hand-over", robot_side.hand_over_s,
                  "on a clean stop, keep replicating up to this long until the peers on both sides hold all it holds")
      ->check(CLI::Range(0.0, 60.0))
      ->capture_default_str();
  cmd->add_option("--store", robot_side.store,
                  "keep both replicas in this directory (DIR/robot and DIR/team, LMDB): a restarted gateway "
                  "reloads them and pulls only what it missed (docs/persistence.md)");
  cmd->add_option("--durability", robot_side.durability, "with --store: none, batch or always (as `quiver agent`)")
      ->check(CLI::IsMember({"none", "batch", "always"}))
      ->capture_default_str();
  cmd->add_flag("--print-team-config", print_team_config, "print the team domain's Cyclone XML and exit");
}

int run_gateway(const GatewayFlags& f) {
  const std::string name = f.name.empty() ? f.robot + "-gateway" : f.name;
  auto log = named_logger(name);
  auto team_file = load_team_file(f.team_file);
  if (!team_file.ok()) {
    log->error("{}", team_file.error().to_string());
    return 2;
  }
  ProcessFlags robot_flags = f.robot_side, team_flags = f.robot_side;
  team_flags.security.clear();  // the robot's credentials are not the team's
  if (!f.robot_side.store.empty()) {
    robot_flags.store = f.robot_side.store + "/robot";
    team_flags.store = f.robot_side.store + "/team";
  }
  auto robot_options = replica_options(name, robot_flags);
  auto team_options = replica_options(name + ".team", team_flags);
  if (!robot_options.ok() || !team_options.ok()) {
    log->error("{}", (robot_options.ok() ? team_options.error() : robot_options.error()).to_string());
    return 2;
  }
  if (!robot_options->replicator.gossip) {
    // Acknowledgements that hold across the gateway (hold queries) are beats of the gossip.
    log->error("a gateway needs gossip membership (--membership gossip)");
    return 2;
  }
  // Each side vouches for the replicas behind it: a claim's acknowledgement from the gateway
  // means every robot holds it, and the peers learn who is alive beyond (docs/teams.md).
  robot_options->replicator.gateway = team_options->replicator.gateway = true;
  robot_options->replicator.robot = team_options->replicator.robot = f.robot;
  team_options->dds.xmit_loss_permille = f.team_loss_permille;
  if (!f.team_security.empty()) {
    auto files = security::agent_files(f.team_security, team_options->name);
    if (!files.ok()) {
      log->error("--team-security: {}", files.error().to_string());
      return 2;
    }
    team_options->dds.security = *files;
  }
  auto team_dds = team_dds_config(*team_file, f.robot, team_options->dds);
  if (!team_dds.ok()) {
    log->error("--robot: {}", team_dds.error().to_string());
    return 2;
  }
  if (f.print_team_config) {
    std::cout << team_dds->xml << std::endl;
    return 0;
  }
  if (team_dds->domain == f.robot_side.domain) {
    // Cyclone binds its receive sockets to every interface: one domain id on both sides would let
    // the team network reach the robot's agents directly.
    log->error("the team domain ({}) must differ from the robot's domain (--domain {})", team_dds->domain,
               f.robot_side.domain);
    return 2;
  }
  team_options->dds = *team_dds;
  robot_options->engine.log = [&](std::string_view line) { log->info("{}", line); };
  team_options->engine.log = [&](std::string_view line) { log->info("team: {}", line); };
  auto robot = DdsReplica::create(*robot_options);
  if (!robot.ok()) {
    log->error("robot domain: {}", robot.error().to_string());
    return 2;
  }
  auto team = DdsReplica::create(*team_options);
  if (!team.ok()) {
    log->error("team domain: {}", team.error().to_string());
    return 2;
  }
  DdsReplica& r = **robot;
  DdsReplica& t = **team;
  for (DdsReplica* x : {&r, &t})
    if (x->store_recovery())
      log->error("{}: the store was set aside and the replica starts empty, to be filled by its peers",
                 x->store_recovery()->to_string());
  stop_on_signals();
  ReplicaReports robot_reports(log), team_reports(log, "team: ");
  robot_reports.attach(r.replicator());
  team_reports.attach(t.replicator());
  route_dds_log([&](const std::string& line) { robot_reports.report(make_error(ErrorCode::kTransport, "DDS: " + line)); });
  struct Unroute {
    ~Unroute() { route_dds_log(nullptr); }
  } unroute;
  ReplicaBridge bridge(r.replicator(), t.replicator());
  log->info("gateway of robot {} in team {}: robot domain {} ({}), team domain {} on {}", f.robot, team_file->team,
            f.robot_side.domain, f.robot_side.dds_config, team_dds->domain, team_file->robot(f.robot)->address);
  const std::int64_t start = monotonic_ns();
  std::int64_t next_status = start;
  while (!stop_requested()) {
    std::int64_t now = monotonic_ns();
    if (f.robot_side.run_for_s > 0 && now - start > static_cast<std::int64_t>(f.robot_side.run_for_s * 1e9)) break;
    r.spin_once(kTurnNs);
    bridge.pump(monotonic_ns());
    t.spin_once(kTurnNs);
    now = monotonic_ns();
    bridge.pump(now);
    robot_reports.tick(now);
    team_reports.tick(now);
    if (f.robot_side.status_ms > 0 && now >= next_status) {
      std::cout << status(name, r, t, bridge).dump() << std::endl;
      next_status = now + f.robot_side.status_ms * 1'000'000LL;
    }
  }
  // A clean stop hands over on both sides: this gateway may hold the only copy of what crossed.
  const auto hand_over = static_cast<std::int64_t>(f.robot_side.hand_over_s * 1e9);
  if (hand_over > 0) {
    if (!r.hand_over(hand_over)) log->warn("left before every agent of the robot held all the gateway holds");
    if (!t.hand_over(hand_over)) log->warn("left before every other gateway held all this one holds");
  }
  std::cout << status(name, r, t, bridge).dump() << std::endl;
  return 0;
}

}  // namespace quiver::agents
