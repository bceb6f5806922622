#pragma once
/// @file
/// A deterministic simulator: N replicas, each a Graph with a Replicator, in one process on a
/// seeded virtual network and clock. Faults: per-link loss, duplication, reordering and delay,
/// partitions (any split, then heal), crash and restart (volatile state lost; the restarted
/// agent comes back under a new incarnation, so it never reuses a dot). A random churn
/// workload runs on all replicas at once; invariants are checked on every replica after every
/// step; after the workload, faults stop, partitions heal, crashed agents restart, and the run
/// continues until every replica has the same digest (converged) or a time limit passes.
///
/// Everything random comes from one generator seeded with `seed`: a seed replays exactly.

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "quiver/agents/replica/replication/replicator.h"
#include "quiver/agents/replica/store/store.h"
#include "quiver/sim/network.h"
#include "quiver/sim/workload.h"

namespace quiver::sim {

/// Agents competing for priority locks on a few scopes while the usual churn goes on.
struct LockWorkload {
  bool enabled = false;
  int scopes = 3;                 ///< scope roots ("scope0", ...) with a small RT subtree each
  int max_priority = 3;           ///< priorities drawn in [1, max_priority]
  std::int64_t lease_ns = 300'000'000;
};

/// Agents move one robot between rooms under a grammar (changeRoom needs a transitable edge);
/// concurrent valid moves can merge into "robot in two rooms", which every replica must flag alike
/// and, with `repair`, the designated agent (agent0) must fix.
struct RoomsWorkload {
  bool enabled = false;
  int rooms = 4;
  bool repair = true;
};

/// Agents keep their replicas in durable stores (agents/replica/store: LMDB, in a temporary directory)
/// on simulated disks driven in virtual time (docs/persistence.md). A crash becomes a power cut:
/// the store loses what it had not written, and the agent restarts from it (reopen, load,
/// restore) instead of empty. Disks fill up for a while, power cuts tear the write in progress,
/// and every agent loses power at once. Flushes (batch) and compactions are made by the
/// simulator at virtual times, so that a seed replays exactly.
struct DiskFaults {
  bool enabled = false;
  agents::Durability durability = agents::Durability::kAlways;
  bool disk_full = false;      ///< episodes in which one agent's disk refuses every write
  bool torn_writes = false;    ///< crashes tear the next write (the power fails during it)
  bool power_cut_all = false;  ///< once during the workload every agent loses power at once
  /// Control: agent 0's disk acknowledges writes it drops. The checks must catch it.
  bool lying_disk = false;
  std::int64_t flush_ns = 20'000'000;      ///< batch: virtual time between flushes
  std::int64_t compact_ns = 150'000'000;   ///< virtual time between compactions of a store
  std::string dir;  ///< where the stores live (empty: a new temporary directory, removed after)
};

/// Robot teams (docs/teams.md): the agents split over `robots` robots (agent i on robot
/// i % robots), each robot its own network with a gateway (two replicas, one on the robot's
/// network and one on the team's, joined by a ReplicaBridge), the team network slower and lossier.
/// Partitions then cut robots off the team network (the robots' own networks never split), and
/// crashes kill agents and gateways.
struct TeamSim {
  int robots = 0;  ///< 0 or 1: one network, no gateway
  double loss = 0.1;  ///< the team network's loss while faults run (at least FaultConfig::loss)
  std::int64_t delay_min_ns = 2'000'000, delay_max_ns = 10'000'000;  ///< the team network's delays
};

struct SimConfig {
  std::uint64_t seed = 1;
  int agents = 5;
  int steps = 200;
  FaultConfig faults;
  ChurnMix mix;
  LockWorkload locks;
  RoomsWorkload rooms;
  DiskFaults disks;
  TeamSim team;
  std::int64_t step_interval_ns = 5'000'000;
  std::int64_t tick_interval_ns = 10'000'000;
  std::int64_t settle_limit_ns = 120'000'000'000;
  bool check_every_step = true;
  /// After the run has converged: this much more virtual time with no workload, its traffic
  /// counted apart (SimResult::idle_bytes, idle_messages) and not in `bytes` and `messages`.
  std::int64_t idle_ns = 0;
  /// A partition into two halves (agents of even and odd index) from a fifth of the workload to
  /// its end, healed with the other faults: `settle_ms` is then the time to converge after it
  /// heals (`quiver bench scale`).
  bool split_until_end = false;
  agents::ReplicatorOptions replicator = default_replicator();
  /// Called once at the end of the run with every replica (all up, converged or not), so a test
  /// can compare what the replicas answer (e.g. transform lookups).
  std::function<void(const std::vector<const graph::Graph*>&)> inspect;
  /// Receives a human-readable line for every fault and phase change (virtual time in ns).
  std::function<void(std::int64_t, const std::string&)> log;
  /// Called after each workload step with (steps done, steps in all), e.g. to show progress.
  std::function<void(int, int)> progress;

  /// Replicator settings scaled for simulated time: short heartbeats and a small relay buffer
  /// so that both recovery paths (buffered deltas and state diffs) are exercised.
  static agents::ReplicatorOptions default_replicator();
};

struct SimResult {
  std::uint64_t seed = 0;
  int agents = 0;
  int steps = 0;
  bool converged = false;
  std::uint64_t invariant_violations = 0;
  std::string first_violation;
  std::string first_rejection;  ///< the first sample a replica refused, and why
  std::string digest;
  std::uint64_t messages = 0;  ///< samples handed to the network, per destination
  /// Their CDR bytes: what DDS would carry as sample payloads (agents/transport/wire).
  std::uint64_t bytes = 0;
  /// What the replicas sent in the idle time after the run (SimConfig::idle_ns): heartbeats and
  /// summaries only, with nothing to replicate.
  std::uint64_t idle_messages = 0, idle_bytes = 0;
  /// `messages` and `bytes` by message kind ("summary", "delta", "pull", "state", "bye").
  std::map<std::string, std::pair<std::uint64_t, std::uint64_t>> by_kind;
  /// Replicator::protocol_bytes() at the end: the largest of any replica, and the mean.
  std::size_t protocol_bytes_max = 0, protocol_bytes_mean = 0;
  std::uint64_t dropped = 0;
  /// Peers introduced by the network's discovery (VirtualNetwork::discover()), not in `messages`.
  std::uint64_t introductions = 0;
  std::uint64_t retransmitted = 0;  ///< reliable samples whose packet was lost and sent again
  std::uint64_t duplicated = 0;
  std::uint64_t ops = 0;  ///< changes committed by the workload
  std::uint64_t crashes = 0;  ///< agents and gateways killed
  std::uint64_t partitions = 0;
  /// Teams (TeamSim): the bytes sent on the team network (part of `bytes`), and the gateways killed.
  int robots = 0;
  std::uint64_t team_bytes = 0, gateway_crashes = 0;
  std::uint64_t deltas_applied = 0;
  std::uint64_t states_applied = 0;
  std::uint64_t rejected_samples = 0;
  std::uint64_t pulls = 0;  ///< pulls sent by the replicas alive at the end
  /// Gossip membership (ReplicatorOptions::gossip), summed over the replicas alive at the end:
  /// suspicions raised, refuted, and peers declared gone.
  std::uint64_t suspicions = 0, refutations = 0, declared_gone = 0;
  std::int64_t virtual_ms = 0;
  std::int64_t settle_ms = 0;  ///< from the end of faults to convergence
  std::size_t final_nodes = 0;
  std::size_t final_edges = 0;
  // Lock workload (zero when disabled).
  std::uint64_t lock_acquired = 0, lock_lost = 0, lock_expired = 0, lock_refused = 0;
  std::int64_t lock_overlap_connected_ns = 0;    ///< two connected agents both held one scope: must be 0
  std::int64_t lock_overlap_partitioned_ns = 0;  ///< both held while unable to hear each other (allowed)
  std::vector<std::int64_t> lock_acquire_latency_ns;  ///< virtual time from acquire() to held
  // Disk faults (DiskFaults).
  std::uint64_t acked = 0;         ///< local commits acknowledged (returned with the host up)
  /// Acknowledged commits of an agent missing from what its store gave back at a restart
  /// (under `always`), or from the final replicas: must be 0.
  std::uint64_t acked_lost = 0;
  std::string first_acked_lost;
  std::uint64_t power_cuts = 0, torn_writes = 0, torn_tails_dropped = 0, writes_refused = 0, fail_stops = 0;
  std::uint64_t store_reloads = 0, records_reloaded = 0, restarts_refused = 0, stores_set_aside = 0;
  std::uint64_t compactions = 0, compactions_failed = 0;
  std::string first_store_error;
  // Rooms workload.
  std::uint64_t moves = 0, moves_refused = 0, violations_seen = 0, repairs = 0, final_violations = 0;

  bool ok() const {
    return converged && invariant_violations == 0 && rejected_samples == 0 && lock_overlap_connected_ns == 0 &&
           acked_lost == 0 && stores_set_aside == 0;
  }
  /// One line of JSON.
  std::string to_json() const;
};

SimResult run_simulation(const SimConfig& config);

/// A fault mix chosen from a schedule number (used to spread many seeds over many mixes):
/// 3 to 16 agents, 0-50% loss, duplication, reordering, partitions and crashes.
SimConfig mixed_config(std::uint64_t seed, int steps);

}  // namespace quiver::sim
