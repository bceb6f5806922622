#pragma once
/// @file
/// The small interface the replication protocol is written against. The simulator's virtual
/// network and the Cyclone DDS transport implement it; the same protocol code runs on both.

#include <cstdint>
#include <span>

#include "quiver/crdt/dot.h"

namespace quiver::agents::inline replica {

/// A peer is one replica (agent incarnation).
using PeerId = crdt::ReplicaId;

struct Envelope;

/// Best-effort delivery of envelopes: one may be lost, duplicated, delayed or reordered; the
/// protocol recovers. Implementations must not call back into the replicator from send().
class Transport {
 public:
  virtual ~Transport() = default;
  /// Sends `e` to `e.to`, or to every other replica when `e.to` is null. A transport may deliver
  /// a unicast envelope to others too: receivers drop what is not addressed to them.
  virtual void send(const Envelope& e) = 0;
};

}  // namespace quiver::agents
