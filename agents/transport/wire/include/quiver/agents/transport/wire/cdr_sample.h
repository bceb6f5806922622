#pragma once
/// @file
/// Quiver's DDS samples as serialized CDR, without any DDS entity: what a rogue participant can
/// put on a topic, decoded as Cyclone's receive path decodes it. For the fuzzers (CDR bytes ->
/// sample -> envelope -> validation -> replicator) and for tests that publish hostile bytes.

#include <cstdint>
#include <span>
#include <vector>

#include "quiver/agents/replica/replication/messages.h"
#include "quiver/base/result.h"

namespace quiver::agents::inline transport {

/// The topics, one per message kind.
enum class DdsTopic : std::uint8_t { kSummary, kDelta, kPull, kState, kBye };
inline constexpr std::size_t kDdsTopicCount = 5;
/// "quiver_summary", "quiver_delta", ...
const char* topic_name(DdsTopic t);

/// Decodes one serialized sample of `topic`: the 4-byte encapsulation header (XCDR1 or XCDR2,
/// either byte order; the only ones Cyclone accepts for these @final types) and the body, as
/// Cyclone 0.10.2 normalizes and reads it, but strict: a sample Cyclone 0.10's XCDR2 bound check
/// would let run past its end is refused. @returns the envelope it carries, unchecked (the
/// replicator validates it), or kMalformed / kTruncated naming what was wrong.
Result<Envelope> decode_cdr_sample(DdsTopic topic, std::span<const std::uint8_t> bytes);

/// Serializes the first message of `e` as a sample of its topic, from `e.from` to `e.to`, as a
/// Cyclone writer would (XCDR version 1 or 2, little- or big-endian).
std::vector<std::uint8_t> encode_cdr_sample(const Envelope& e, int xcdr_version = 1, bool little_endian = true);
/// The topic of a message.
DdsTopic topic_of(const Message& m);

}  // namespace quiver::agents
