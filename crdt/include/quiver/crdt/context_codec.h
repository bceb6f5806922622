#pragma once
/// @file
/// Wire form of a CausalContext: per replica its id, its version-vector entry and its cloud
/// ranges, gap-encoded.
///
/// Threading: thread-safe on distinct readers, writers and contexts. Decoding failures are
/// recorded in the bytes::Reader (never thrown): check r.ok() afterwards.

#include "quiver/crdt/causal_context.h"
#include "quiver/base/byte_codec.h"

namespace quiver::crdt {

/// Appends the wire form of `c` to `w`; decode_context() reads it back to an equal context.
void encode_context(const CausalContext& c, bytes::Writer& w);
/// Decodes into `out` (cleared). Failures are recorded in the reader.
/// Records kTooLarge (more than `max_replicas` replicas or `max_ranges` ranges in all),
/// kTruncated, or kMalformed (ranges not ascending, disjoint and nonzero); `out` then holds
/// what was read before the failure and must be discarded.
void decode_context(bytes::Reader& r, CausalContext& out, std::uint64_t max_replicas = 1u << 16,
                    std::uint64_t max_ranges = 1u << 24);

/// Appends a replica id: agent as fixed64, incarnation as varint.
void encode_replica(const ReplicaId& id, bytes::Writer& w);
/// Reads a replica id written by encode_replica(); failures name `field`.
/// @returns the id; unspecified (to be discarded) once r.ok() is false.
/// @pre `field` is a NUL-terminated string (copied into the error only if reading fails).
ReplicaId decode_replica(bytes::Reader& r, const char* field);

}  // namespace quiver::crdt
