#pragma once
// What a store keeps of a replica killed in the simulator (AgentHostOptions::durable): its state
// and its (origin, seq) set, loaded again under the same replica id when it boots. The agent host
// keeps one per agent, a gateway one per side. Threading: the simulator's one thread.
#include <memory>

#include "quiver/agents/replica/replication/replicator.h"
#include "quiver/crdt/causal_context.h"
#include "quiver/graph/graph.h"

namespace quiver::sim {

struct KeptReplica {
  std::unique_ptr<graph::GraphDelta> state;  // null: nothing kept
  crdt::CausalContext applied;

  static KeptReplica of(const graph::Graph& g, const agents::Replicator& r) {
    return KeptReplica{std::make_unique<graph::GraphDelta>(g.state()), r.applied()};
  }
  explicit operator bool() const { return state != nullptr; }
};

}  // namespace quiver::sim
