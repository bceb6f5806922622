#pragma once
/// @file
/// The small interface the replication protocol is written against. The simulator's virtual
/// network and the Cyclone DDS transport implement it; the same protocol code runs on both.

#include <cstdint>
#include <span>

#include "quiver/crdt/dot.h"

namespace quiver::agents {

/// A peer is one replica (agent incarnation).
using PeerId = crdt::ReplicaId;

/// Best-effort datagram delivery of whole frames: a frame may be lost, duplicated, delayed or
/// reordered, but never corrupted into another valid frame undetected (the protocol validates).
/// Implementations must not call back into the replicator from inside send/broadcast.
class Transport {
 public:
  virtual ~Transport() = default;
  /// Sends `frame` to every other replica.
  virtual void broadcast(std::span<const std::uint8_t> frame) = 0;
  /// Sends `frame` to one replica (a transport may deliver it to others too: frames carry
  /// their destination and receivers drop what is not theirs).
  virtual void send(const PeerId& to, std::span<const std::uint8_t> frame) = 0;
};

}  // namespace quiver::agents
