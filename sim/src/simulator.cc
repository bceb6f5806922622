// The replica simulator's public face (simulator.h): run_simulation(), SimConfig's defaults and
// the mixed configurations of the tests, SimResult as JSON. The simulation itself:
// replica_simulation.h.
#include "quiver/sim/simulator.h"

#include <nlohmann/json.hpp>

#include "quiver/base/rng.h"
#include "replica_simulation.h"

namespace quiver::sim {

agents::ReplicatorOptions SimConfig::default_replicator() {
  agents::ReplicatorOptions o;
  o.heartbeat_ns = 50'000'000;
  o.lease_ns = 400'000'000;
  o.pull_timeout_ns = 200'000'000;
  o.pull_first_timeout_ns = 50'000'000;
  o.gap_grace_ns = 40'000'000;
  o.buffer_bytes = 24u << 10;
  o.chunk_bytes = 2u << 10;
  // Gossip membership is off here (the library's default) and on in `quiver sim` and `quiver
  // bench scale`; its periods are scaled for simulated time like the rest.
  o.probe_ns = 300'000'000;
  o.rediscover_ns = 2'000'000'000;
  return o;
}

std::string SimResult::to_json() const {
  nlohmann::json j;
  j["seed"] = seed;
  j["agents"] = agents;
  j["steps"] = steps;
  j["converged"] = converged;
  j["invariant_violations"] = invariant_violations;
  if (!first_violation.empty()) j["first_violation"] = first_violation;
  if (!first_rejection.empty()) j["first_rejection"] = first_rejection;
  j["digest"] = digest;
  j["messages"] = messages;
  j["bytes"] = bytes;
  j["pulls"] = pulls;
  if (suspicions + refutations + declared_gone > 0) {
    j["suspicions"] = suspicions;
    j["refutations"] = refutations;
    j["declared_gone"] = declared_gone;
  }
  for (const auto& [kind, mb] : by_kind)
    if (mb.first > 0) j["by_kind"][kind] = {{"messages", mb.first}, {"bytes", mb.second}};
  if (protocol_bytes_max > 0) {
    j["protocol_bytes_max"] = protocol_bytes_max;
    j["protocol_bytes_mean"] = protocol_bytes_mean;
  }
  j["dropped"] = dropped;
  if (introductions > 0) j["introductions"] = introductions;
  j["retransmitted"] = retransmitted;
  j["duplicated"] = duplicated;
  j["ops"] = ops;
  j["crashes"] = crashes;
  j["partitions"] = partitions;
  if (robots > 0) {
    j["robots"] = robots;
    j["team_bytes"] = team_bytes;
    j["gateway_crashes"] = gateway_crashes;
  }
  j["deltas_applied"] = deltas_applied;
  j["states_applied"] = states_applied;
  j["rejected_samples"] = rejected_samples;
  j["final_nodes"] = final_nodes;
  j["final_edges"] = final_edges;
  if (moves + moves_refused > 0) {
    j["moves"] = moves;
    j["moves_refused"] = moves_refused;
    j["violations_seen"] = violations_seen;
    j["repairs"] = repairs;
    j["final_violations"] = final_violations;
  }
  if (lock_acquired + lock_lost + lock_expired + lock_refused > 0) {
    j["lock_acquired"] = lock_acquired;
    j["lock_lost"] = lock_lost;
    j["lock_expired"] = lock_expired;
    j["lock_refused"] = lock_refused;
    j["lock_overlap_connected_ms"] = lock_overlap_connected_ns / 1e6;
    j["lock_overlap_partitioned_ms"] = lock_overlap_partitioned_ns / 1e6;
  }
  if (power_cuts + fail_stops + store_reloads > 0) {
    j["acked"] = acked;
    j["acked_lost"] = acked_lost;
    if (!first_acked_lost.empty()) j["first_acked_lost"] = first_acked_lost;
    j["power_cuts"] = power_cuts;
    j["torn_writes"] = torn_writes;
    j["torn_tails_dropped"] = torn_tails_dropped;
    j["writes_refused"] = writes_refused;
    j["fail_stops"] = fail_stops;
    j["store_reloads"] = store_reloads;
    j["records_reloaded"] = records_reloaded;
    j["restarts_refused"] = restarts_refused;
    j["stores_set_aside"] = stores_set_aside;
    j["compactions"] = compactions;
    j["compactions_failed"] = compactions_failed;
    if (!first_store_error.empty()) j["first_store_error"] = first_store_error;
  }
  j["virtual_ms"] = virtual_ms;
  j["settle_ms"] = settle_ms;
  return j.dump();
}

SimResult run_simulation(const SimConfig& config) { return Simulation(config).run(); }

SimConfig mixed_config(std::uint64_t seed, int steps) {
  Rng r(seed ^ 0x6d69786564ULL);
  SimConfig c;
  c.seed = seed;
  c.steps = steps;
  c.agents = 3 + static_cast<int>(r.below(14));
  const double losses[] = {0.0, 0.05, 0.2, 0.5};
  c.faults.loss = losses[r.below(4)];
  c.faults.dup = r.chance(0.5) ? 0.1 : 0.0;
  c.faults.reorder = r.chance(0.5);
  c.faults.partitions = r.chance(0.5);
  c.faults.crashes = r.chance(0.5);
  return c;
}

}  // namespace quiver::sim
