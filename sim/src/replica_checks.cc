// The replica simulator's checks: graph invariants on every replica, the time two agents both
// held one lock scope (connected or partitioned), and convergence (same applied dots, same digest;
// with a team, both sides of every gateway too).
#include <algorithm>

#include "replica_simulation.h"

namespace quiver::sim {

// Time two agents both hold one scope, split by whether they can hear each other.
void Simulation::account_overlap() {
  if (!cfg_.locks.enabled) return;
  bool connected = false, partitioned = false;
  for (std::size_t s = 0; s < scope_roots_.size() && !connected; ++s) {
    const graph::NodeId root = scope_roots_[s];
    std::vector<int> holders;
    for (int i = 0; i < cfg_.agents; ++i) {
      Agent& a = agents_[i];
      if (!a.up) continue;
      if (a.graph->has_node(root) && a.locks->holds(root)) holders.push_back(i);
    }
    for (std::size_t x = 0; x < holders.size(); ++x)
      for (std::size_t y = x + 1; y < holders.size(); ++y) {
        Agent& a = agents_[holders[x]];
        Agent& b = agents_[holders[y]];
        // Across robots the gateways' hearing each other stands for the agents' (linked()).
        const bool across = robots() > 0 && robot_of(holders[x]) != robot_of(holders[y]);
        bool hear = linked(holders[x], holders[y]) &&
                    (across || (a.replicator->peer_alive(b.graph->replica()) && b.replicator->peer_alive(a.graph->replica())));
        (hear ? connected : partitioned) = true;
      }
  }
  if (overlap_since_connected_ >= 0) result_.lock_overlap_connected_ns += net_.now() - overlap_since_connected_;
  if (overlap_since_partitioned_ >= 0) result_.lock_overlap_partitioned_ns += net_.now() - overlap_since_partitioned_;
  overlap_since_connected_ = connected ? net_.now() : -1;
  overlap_since_partitioned_ = partitioned ? net_.now() : -1;
  if (connected && result_.first_violation.empty())
    result_.first_violation = "t=" + std::to_string(net_.now()) + "ns: two connected agents both hold a scope";
}

void Simulation::check_invariants_all() {
  for (auto& a : agents_) {
    if (!a.up) continue;
    auto v = a.graph->check_invariants();
    if (!v.empty() && result_.first_violation.empty())
      result_.first_violation = "t=" + std::to_string(net_.now()) + "ns agent " + a.graph->replica().to_string() + ": " + v[0];
    result_.invariant_violations += v.size();
  }
}

// Two agents that can hear each other: in one group of one network, or, on different robots,
// through their gateways: both up, their team sides in one group and hearing each other, each agent
// hearing its gateway, whose list of the replicas behind it holds the other agent, and having heard
// its latest generation (docs/teams.md). What a lock guarantees across robots holds between such agents, as within one
// network it holds between agents that hear each other.
bool Simulation::linked(int x, int y) const {
  if (net_.group(x) != net_.group(y)) return false;
  if (robots() == 0 || robot_of(x) == robot_of(y)) return true;
  const int rx = robot_of(x), ry = robot_of(y);
  const SimGateway& gx = gateways_[rx];
  const SimGateway& gy = gateways_[ry];
  if (!gx.up || !gy.up || net_.group(gateway_node(rx, 1)) != net_.group(gateway_node(ry, 1)) ||
      !gx.replicator[1]->peer_alive(gy.graph[1]->replica()) || !gy.replicator[1]->peer_alive(gx.graph[1]->replica()))
    return false;
  // Each robot's gateway lists the other agent among those alive behind it.
  for (auto [agent, other] : {std::pair{x, y}, std::pair{y, x}}) {
    const auto& told = gateways_[robot_of(agent)].replicator[0]->members_behind();
    const agents::PeerId want = agents_[other].graph->replica();
    if (std::none_of(told.begin(), told.end(), [&](const agents::Member& m) { return m.id == want; })) return false;
  }
  for (auto [agent, r] : {std::pair{x, rx}, std::pair{y, ry}}) {
    const SimGateway& g = gateways_[r];
    const agents::Replicator& mine = *agents_[agent].replicator;
    // (A gateway without the role, -1, announces no generation: nothing to wait for.)
    const int heard = mine.generation_heard(g.graph[0]->replica());
    if (!mine.peer_alive(g.graph[0]->replica()) ||
        (heard >= 0 && heard != static_cast<int>(g.replicator[0]->behind_generation() & 63)))
      return false;
  }
  return true;
}

bool Simulation::converged() {
  const Agent& first = agents_[0];
  if (!first.up) return false;  // a host down (fail-stopped) has no graph to compare
  Digest128 d = first.graph->digest();
  for (const auto& a : agents_) {
    if (!a.up) return false;
    if (!(a.replicator->applied() == first.replicator->applied())) return false;
    if (!(a.graph->digest() == d)) return false;
  }
  if (robots() > 0 && !gateways_converged(d, first.replicator->applied())) return false;
  // With a repairing agent, quiescence also means the repairs are done.
  if (cfg_.rooms.enabled && cfg_.rooms.repair && !first.guard->checker().all_violations(*first.graph).empty())
    return false;
  return true;
}

}  // namespace quiver::sim
