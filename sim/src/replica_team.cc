// The replica simulator's robot teams (TeamSim, docs/teams.md): each robot its own network
// (segment r) with its agents and one side of its gateway, the team network (segment `robots`)
// with the gateways' other sides, slower and lossier; a gateway's two replicas are joined by a
// ReplicaBridge, pumped after every sample either side receives and every tick. Partitions cut
// robots off the team network; a gateway killed loses both replicas and restarts empty.
#include "replica_simulation.h"

namespace quiver::sim {

void Simulation::make_team() {
  const int n = robots();
  gateways_.resize(static_cast<std::size_t>(n));
  for (int i = 0; i < cfg_.agents; ++i) net_.set_segment(i, robot_of(i));
  for (int r = 0; r < n; ++r) {
    net_.set_segment(gateway_node(r, 0), r);
    net_.set_segment(gateway_node(r, 1), n);
  }
  FaultConfig team = cfg_.faults;
  team.loss = std::max(cfg_.faults.loss, cfg_.team.loss);
  team.delay_min_ns = cfg_.team.delay_min_ns;
  team.delay_max_ns = std::max(cfg_.team.delay_min_ns, cfg_.team.delay_max_ns);
  net_.set_segment_faults(n, team);
}

int Simulation::gateway_index(const std::string& name) const {
  for (int r = 0; r < robots(); ++r)
    if (name == "gateway" + std::to_string(r)) return r;
  return -1;
}

SimGateway::Place Simulation::gateway_place(int r) const {
  SimGateway::Place at;
  at.node[0] = gateway_node(r, 0);
  at.node[1] = gateway_node(r, 1);
  at.replica_base = 0x6100 + 2 * static_cast<std::uint64_t>(r);
  at.name = "gateway" + std::to_string(r);
  at.robot = "robot" + std::to_string(r);
  return at;
}

void Simulation::boot_gateway(int r) {
  SimGateway& g = gateways_[r];
  g.boot(net_, gateway_place(r), cfg_.replicator, [this](const std::string& name, const Error& e) {
    const std::string line = name + " rejected: " + e.to_string();
    if (result_.first_rejection.empty()) result_.first_rejection = "t=" + std::to_string(net_.now()) + "ns " + line;
    note(line);
  });
  if (g.incarnation > 1) note("gateway" + std::to_string(r) + " restarts empty (incarnation " + std::to_string(g.incarnation) + ")");
}

void Simulation::crash_gateway(int r) {
  SimGateway& g = gateways_[r];
  if (!g.up) return;
  result_.rejected_samples += g.crash(net_, gateway_place(r));
  ++result_.crashes;
  ++result_.gateway_crashes;
  note("gateway" + std::to_string(r) + " crashes (kill -9: both its replicas are lost)");
}

void Simulation::tick_gateway(int r) {
  gateways_[r].tick(net_.now());
  net_.at(net_.now() + cfg_.tick_interval_ns, [this, r] { tick_gateway(r); });
}

// Robots named in one group share the team network; the robots' own networks stay whole.
void Simulation::team_partition(const std::vector<std::vector<std::string>>& groups) {
  for (int r = 0; r < robots(); ++r) net_.set_group(gateway_node(r, 1), static_cast<int>(groups.size()));
  for (std::size_t k = 0; k < groups.size(); ++k)
    for (const std::string& name : groups[k])
      for (int r = 0; r < robots(); ++r)
        if (name == "robot" + std::to_string(r)) net_.set_group(gateway_node(r, 1), static_cast<int>(k));
}

void Simulation::team_heal() {
  if (FaultConfig* team = net_.segment_faults(robots())) {
    team->loss = 0;
    team->dup = 0;
  }
  for (int r = 0; r < robots(); ++r)
    if (!gateways_[r].up) boot_gateway(r);
}

// Once converged, and half a second later, every agent knows every other agent alive (directly,
// or behind its gateway), so that a lock any of them holds is alive for all: a violation otherwise.
void Simulation::check_team_members() {
  net_.run_until(net_.now() + 500'000'000);
  for (int x = 0; x < cfg_.agents; ++x)
    for (int y = 0; y < cfg_.agents; ++y) {
      if (x == y || !agents_[x].up || !agents_[y].up) continue;
      if (agents_[x].replicator->member_alive(agents_[y].graph->replica())) continue;
      ++result_.invariant_violations;
      if (result_.first_violation.empty())
        result_.first_violation = "t=" + std::to_string(net_.now()) + "ns: agent" + std::to_string(x) + " (robot " +
                                  std::to_string(robot_of(x)) + ") does not know agent" + std::to_string(y) + " (robot " +
                                  std::to_string(robot_of(y)) + ") alive";
    }
}

bool Simulation::gateways_converged(const Digest128& d, const crdt::CausalContext& applied) const {
  for (const SimGateway& g : gateways_) {
    if (!g.up) return false;
    for (int side = 0; side < 2; ++side)
      if (!(g.replicator[side]->applied() == applied) || !(g.graph[side]->digest() == d)) return false;
  }
  return true;
}

}  // namespace quiver::sim
