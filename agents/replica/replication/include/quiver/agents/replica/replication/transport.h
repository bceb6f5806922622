#pragma once
/// @file
/// The small interface the replication protocol is written against. The simulator's virtual
/// network and the Cyclone DDS transport implement it; the same protocol code runs on both.

#include <cstdint>
#include <span>
#include <string>

#include "quiver/crdt/dot.h"

namespace quiver::agents::inline replica {

/// A peer is one replica (agent incarnation).
using PeerId = crdt::ReplicaId;

struct Sample;

/// What a transport's own discovery says of a peer (over DDS, its participant's user data; in
/// the simulator, its network): the replica id, and the name and role it announces. Untrusted:
/// Replicator::introduce() takes the name only if it hashes to the id.
struct PeerCard {
  PeerId id;
  std::string name;
  bool observer = false;
  bool gateway = false;  ///< one side of a gateway (docs/teams.md)
};

/// Best-effort delivery of samples (one protocol message each): one may be lost, duplicated,
/// delayed or reordered; the protocol recovers. Every transport carries a sample as the CDR
/// encoding of its IDL type (agents/transport/wire), so the bytes the simulator moves are the
/// bytes DDS ships.
class Transport {
 public:
  virtual ~Transport() = default;
  /// Sends `s` to `s.to`, or to every other replica when `s.to` is null. A transport may deliver
  /// a unicast sample to others too: receivers drop what is not addressed to them.
  /// @pre `s.from` is this transport's replica. Must not call back into the replicator.
  /// Threading: the replicator calls it on its owner thread; whether other threads may call it
  /// too is the implementation's (DdsTransport::send() is thread-safe). Errors are the
  /// transport's to count: send() reports nothing (best effort).
  virtual void send(const Sample& s) = 0;
};

}  // namespace quiver::agents
