#pragma once
// What a forger sends: a delta under `origin`'s name over sequence numbers [lo, hi] creating one
// node of `type` named `name`, whose id is `dot` (the hardening tests, the attack schedules and
// the rogue participant all build their forgeries with it).

#include <memory>
#include <string>
#include <vector>

#include "quiver/graph/codec.h"
#include "quiver/graph/delta.h"

namespace quiver::testing {

inline graph::GraphDelta forged_node_delta(const graph::ReplicaId& origin, std::uint64_t lo, std::uint64_t hi,
                                           graph::Dot dot, const std::string& type, const std::string& name) {
  graph::GraphDelta d;
  d.origin = origin;
  d.seq_lo = lo;
  d.seq_hi = hi;
  d.context.add_range(dot.replica, dot.counter, dot.counter);
  graph::GraphDelta::NodeOp op;
  op.id = graph::NodeId{dot};
  op.has_header = true;
  op.type = graph::Symbol(type);
  op.name = name;
  d.nodes.push_back(op);
  return d;
}

inline std::shared_ptr<const std::vector<std::uint8_t>> bytes_of(const graph::GraphDelta& d) {
  return std::make_shared<const std::vector<std::uint8_t>>(graph::encode(d));
}

}  // namespace quiver::testing
