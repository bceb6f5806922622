// The replica simulator's checks: graph invariants on every replica, the time two agents both
// held one lock scope (connected or partitioned), and convergence (same applied dots, same digest).
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
        bool hear = net_.group(holders[x]) == net_.group(holders[y]) && a.replicator->peer_alive(b.graph->replica()) &&
                    b.replicator->peer_alive(a.graph->replica());
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

bool Simulation::converged() {
  const Agent& first = agents_[0];
  if (!first.up) return false;  // a host down (fail-stopped) has no graph to compare
  Digest128 d = first.graph->digest();
  for (const auto& a : agents_) {
    if (!a.up) return false;
    if (!(a.replicator->applied() == first.replicator->applied())) return false;
    if (!(a.graph->digest() == d)) return false;
  }
  // With a repairing agent, quiescence also means the repairs are done.
  if (cfg_.rooms.enabled && cfg_.rooms.repair && !first.guard->checker().all_violations(*first.graph).empty())
    return false;
  return true;
}

}  // namespace quiver::sim
