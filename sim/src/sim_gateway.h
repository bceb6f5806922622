#pragma once
// A robot team's gateway in the simulator, as `quiver gateway` runs it (docs/teams.md): two
// replicas, one on its robot's network and one on the team's, joined by a ReplicaBridge that is
// pumped after every sample either side receives and every tick. Killed, both replicas vanish;
// booted again, it starts empty under a new incarnation, or, with a store (`quiver gateway
// --store`), from what its replicas had joined under the incarnation the store kept. Used by the
// replica simulator (replica_team.cc) and the agent host (agent_host.cc). Threading: the
// simulator's one thread.
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "quiver/agents/replica/replication/bridge.h"
#include "quiver/agents/replica/replication/replicator.h"
#include "quiver/graph/graph.h"
#include "quiver/sim/network.h"
#include "kept_replica.h"

namespace quiver::sim {

struct SimGateway {
  bool up = false;
  std::uint64_t incarnation = 0;
  std::unique_ptr<graph::Graph> graph[2];
  std::unique_ptr<agents::Replicator> replicator[2];
  std::unique_ptr<agents::ReplicaBridge> bridge;  // last: destroyed first
  KeptReplica stored[2];  // its store (crash(..., keep = true)), one per side

  /// Where it lives: network nodes `node[0]` (robot side) and `node[1]` (team side), its replica
  /// ids `replica_base` + side, its name (the team side's with ".team") and its robot's name.
  struct Place {
    int node[2] = {-1, -1};
    std::uint64_t replica_base = 0;
    std::string name, robot;
  };
  /// Boots both sides and makes them known to their networks: from its store under the same
  /// incarnation when the last crash kept one, else a fresh incarnation with empty replicas.
  /// `on_error` hears each side's rejections (its name, the error). @returns whether it booted
  /// from its store.
  bool boot(VirtualNetwork& net, const Place& at, const agents::ReplicatorOptions& base,
            std::function<void(const std::string& side_name, const Error& e)> on_error);
  /// kill -9: both replicas vanish at once; with `keep`, its store keeps what they had joined.
  /// @returns the samples they had rejected.
  std::uint64_t crash(VirtualNetwork& net, const Place& at, bool keep = false);
  /// Both replicators' ticks and a pump of the bridge (nothing while down).
  void tick(std::int64_t now);
};

}  // namespace quiver::sim
