#pragma once
/// @file
/// Which changes a replica admits, by who made them. Without an Admission a Replicator joins
/// every well-formed delta and state (the protocol alone, docs/protocol.md); with one, every
/// delta is signed by its origin when published and checked on arrival against the origin's
/// identity and its graph-level permissions (agents/rules/permissions, docs/security.md).
///
/// The decision must depend on the delta and the policy only, never on what the receiving
/// replica holds, so that every replica decides alike and replicas that refuse a delta stay equal.
/// The one exception is the fast path (admit_delta()'s `sender`): a delta straight from its
/// authenticated origin is admitted without verifying the signature, so a member that signs its
/// own deltas badly on purpose is admitted by the replicas it sent them to and refused by those
/// that got them relayed; their (origin, seq) sets are equal and their digests differ, and the
/// digest repair makes them converge (docs/security.md).
///
/// Threading: the Replicator calls every method on its owner thread. Implementations return
/// refusals as values; an exception (e.g. a signing failure inside OpenSSL) propagates out of the
/// commit or on_sample() that caused the call.

#include <cstdint>
#include <span>
#include <vector>

#include "quiver/agents/replica/replication/transport.h"
#include "quiver/graph/delta.h"
#include "quiver/base/result.h"

namespace quiver::agents::inline replica {

class Admission {
 public:
  virtual ~Admission() = default;
  /// The signature this replica attaches to a delta it publishes (codec bytes); empty: none.
  /// Called when the delta is published (inside its commit, or in flush() when coalescing).
  /// Owner thread of the replicator.
  /// @returns at most SampleLimits::max_signature_bytes bytes (longer ones make every receiver
  ///          refuse the sample).
  virtual std::vector<std::uint8_t> sign(std::span<const std::uint8_t> payload) = 0;
  /// Called after the replica sent a delta that sign() signed: time to prepare what the next
  /// signature needs (Signer::prepare()), off the path of the one just sent. Owner thread.
  virtual void prepare() {}
  /// Ok, or why the delta `d` (decoded from `payload`; its origin is d.origin) must not be
  /// applied. `signature` is what came with it (empty: none). `sender` is the participant that
  /// sent the sample as the transport authenticated it (Sample::sender; empty when it
  /// authenticates nobody): when it is the origin's own, the origin's signature need not be
  /// verified (docs/security.md, "The fast path"). Owner thread of the replicator.
  /// @returns OK to apply; any error refuses the delta (the replicator reports it as
  ///          kPermissionDenied with this error's message).
  virtual Status admit_delta(const graph::GraphDelta& d, std::span<const std::uint8_t> payload,
                             std::span<const std::uint8_t> signature, std::span<const std::uint8_t> sender) = 0;
  /// Ok, or why the state fragment `state` that `from` sent must not be joined.
  /// Owner thread of the replicator.
  /// @returns OK to join; any error drops the whole transfer (reported as kPermissionDenied).
  virtual Status admit_state(const PeerId& from, const graph::GraphDelta& state) = 0;
};

}  // namespace quiver::agents
