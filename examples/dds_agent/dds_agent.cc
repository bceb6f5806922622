// A replicating agent over Cyclone DDS, on the embedded loopback configuration (nothing leaves
// this machine): it announces itself in the shared graph, prints what its peers change and
// leaves after SECONDS (default 2). Start several (dds_agent NAME SECONDS) to see them meet.
#include <cstdio>
#include <string>

#include "quiver/agents/runtime/process/dds_replica.h"

int main(int argc, char** argv) {
  quiver::agents::DdsReplicaOptions o;
  o.name = argc > 1 ? argv[1] : "speech";  // o.dds defaults to the loopback configuration
  const double seconds = argc > 2 ? std::stod(argv[2]) : 2.0;
  auto created = quiver::agents::DdsReplica::create(o);
  if (!created.ok()) {
    std::fprintf(stderr, "%s\n", created.error().to_string().c_str());
    return 1;
  }
  auto& agent = *created;
  agent->graph().subscribe([](const quiver::graph::ChangeBatch& b) {  // on the agent's thread
    if (!b.local) std::printf("%zu node changes from %s\n", b.nodes.size(), b.origin.to_string().c_str());
  });

  auto tx = agent->graph().begin();
  auto me = tx.create_node("agent", o.name + "-" + agent->id().to_string());
  auto committed = tx.commit();  // broadcast at once to every peer on the domain
  if (!me.ok() || !committed.ok()) return 1;

  // This thread owns the replica while it spins; spin() runs until stop() from anywhere.
  agent->spin_for(static_cast<std::int64_t>(seconds * 1e9));
  std::printf("%s: %zu nodes, %zu live peers\n", o.name.c_str(), agent->graph().node_count(),
              agent->replicator().live_peer_count());
  return 0;
}
