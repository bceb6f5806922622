// A graph-only program (quiver::graph: no DDS, FCL or urdfdom): one replica, one transaction,
// a subscription and a read.
#include <cstdio>

#include "quiver/graph/graph.h"
using namespace quiver::graph;

int main() {
  Graph g(ReplicaId{quiver::fnv1a64("speech"), /*incarnation=*/1});
  g.subscribe([](const ChangeBatch& b) {  // created / updated / deleted, local or from whom
    std::printf("%zu node and %zu edge changes from %s\n", b.nodes.size(), b.edges.size(),
                b.origin.to_string().c_str());
  });

  auto tx = g.begin();
  NodeId robot = *tx.create_node("robot", "robot", {{Symbol("battery"), Value(0.9)}});
  NodeId person = *tx.create_node("person", "person");
  auto edge = tx.insert_edge(robot, person, Symbol("speaking"), {{Symbol("text"), Value("Hello")}});
  auto committed = tx.commit();  // one delta, published to the delta sink
  if (!edge.ok() || !committed.ok()) return 1;

  double battery = g.get<double>(robot, "battery").value();
  std::printf("battery %.2f; %zu nodes, %zu edges\n", battery, g.node_count(), g.edge_count());
  return 0;
}
