#pragma once
/// @file
/// Wire form of a CausalContext: per replica its id, its version-vector entry and its cloud
/// ranges, gap-encoded.

#include "quiver/crdt/causal_context.h"
#include "quiver/base/byte_codec.h"

namespace quiver::crdt {

void encode_context(const CausalContext& c, bytes::Writer& w);
/// Decodes into `out` (cleared). Failures are recorded in the reader.
void decode_context(bytes::Reader& r, CausalContext& out, std::uint64_t max_replicas = 1u << 16,
                    std::uint64_t max_ranges = 1u << 24);

void encode_replica(const ReplicaId& id, bytes::Writer& w);
ReplicaId decode_replica(bytes::Reader& r, const char* field);

}  // namespace quiver::crdt
