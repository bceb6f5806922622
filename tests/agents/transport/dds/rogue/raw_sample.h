#pragma once
// Test-only: publishes arbitrary serialized bytes as a sample of a Quiver topic, so that the
// rogue participant can put on the wire what no well-behaved writer would (malformed CDR,
// truncated or oversized samples). Cyclone 0.10.2 has no API for it: a serdata with our own ops
// carries the bytes, and the writer's sertype is found by taking one sample back (0.10.2 has no
// dds_get_entity_sertype()).

#include <dds/dds.h>

#include <cstdint>
#include <span>

struct ddsi_sertype;

namespace quiver::rogue {

/// The sertype of `topic`'s writers, found with a private writer/reader pair on that topic.
/// `valid_sample` is any well-formed sample of the topic's type. Null on failure.
const ddsi_sertype* probe_sertype(dds_entity_t participant, dds_entity_t topic, const void* valid_sample);

/// Writes `bytes` (a 4-byte encapsulation header and a body, any content) as one sample.
/// @returns dds_writecdr's return code.
dds_return_t write_raw(dds_entity_t writer, const ddsi_sertype* type, std::span<const std::uint8_t> bytes);

}  // namespace quiver::rogue
