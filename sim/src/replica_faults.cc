// The replica simulator's faults: one schedule drawn by the simulator's random generator
// (fault_generator.h) and played by name on the simulation (FaultTarget, fault_model.h).
#include <algorithm>

#include "quiver/sim/fault_generator.h"
#include "replica_simulation.h"

namespace quiver::sim {

int Simulation::index(const std::string& agent) const {
  for (int i = 0; i < cfg_.agents; ++i)
    if (agent == name(i)) return i;
  return -1;
}

// With FaultConfig::partitions, 1 to 3 partitions one after another during the workload, each
// into 2 to 4 groups (none empty), healed 50 ms to 1.55 s later, the last by the end of the work.
// With FaultConfig::crashes, 1 to N/3 kill -9 of any agent during the workload, each restarted
// 20 ms to 1.52 s later, or at the heal when that falls after the work. The links' loss is the
// network's (FaultConfig::loss) all along.
void Simulation::plan_faults(std::int64_t work_end) {
  const bool partitions = cfg_.faults.partitions && cfg_.agents >= 2;
  if (!partitions && !cfg_.faults.crashes) return;
  const double end_s = static_cast<double>(work_end) / 1e9;
  FaultMix mix;
  for (int i = 0; i < cfg_.agents; ++i) mix.agents.push_back(name(i));
  std::vector<std::string> killable = mix.agents;
  if (robots() > 0) {
    // A team: partitions cut robots off the team network; gateways may be killed too.
    mix.agents.clear();
    for (int r = 0; r < robots(); ++r) {
      mix.agents.push_back("robot" + std::to_string(r));
      killable.push_back("gateway" + std::to_string(r));
    }
  }
  mix.loss_chance = 0;
  mix.max_partitions = 0;
  mix.max_kills = 0;
  if (partitions) {
    mix.min_partitions = 1;
    mix.max_partitions = 3;
    mix.max_groups = 4;
    mix.fill_groups = true;
    mix.partitions_in_turn = true;
    mix.partition_at = {0, end_s};
    mix.heal_after = {0.05, 1.55};
  }
  if (cfg_.faults.crashes) {
    mix.killable = killable;
    mix.min_kills = 1;
    mix.max_kills = std::max(1, cfg_.agents / 3);
    mix.kill_at = {0, end_s};
    mix.restart_after = {0.02, 1.52};
    mix.restarts_until = end_s;
  }
  schedule_faults(*this, random_faults(rng_, mix), cfg_.log, fault_counts_);
}

void Simulation::partition(const std::vector<std::vector<std::string>>& groups) {
  ++result_.partitions;
  if (robots() > 0) return team_partition(groups);
  for (int i = 0; i < cfg_.agents; ++i) net_.set_group(i, static_cast<int>(groups.size()));  // not named
  for (std::size_t g = 0; g < groups.size(); ++g)
    for (const std::string& n : groups[g])
      if (const int i = index(n); i >= 0) net_.set_group(i, static_cast<int>(g));
}

void Simulation::heal() { net_.heal(); }

// A kill -9; with torn writes, half of them instead make the power fail during the next write of
// the agent's store (the host goes down then, and restarts shortly after: after_write).
bool Simulation::kill(const std::string& agent) {
  if (const int r = gateway_index(agent); r >= 0) {
    if (!gateways_[r].up) return false;
    crash_gateway(r);
    return true;
  }
  const int i = index(agent);
  if (i < 0 || !agents_[i].up) return false;
  if (cfg_.disks.enabled && cfg_.disks.torn_writes && rng_.chance(0.5)) {
    agents_[i].disk.tear_next = true;
    return true;
  }
  crash(i);
  return true;
}

bool Simulation::restart(const std::string& agent) {
  if (const int r = gateway_index(agent); r >= 0) {
    if (gateways_[r].up) return false;
    boot_gateway(r);
    return true;
  }
  const int i = index(agent);
  if (i < 0 || agents_[i].up) return false;
  boot(i);
  return true;
}

void Simulation::set_loss(double p) { net_.faults().loss = p; }

}  // namespace quiver::sim
