#pragma once
/// @file
/// The protocol's samples as serialized CDR: the bytes Cyclone DDS ships for a message (its IDL
/// type, idl/quiver_wire.idl, serialized by Cyclone's own serializer), without any DDS entity.
/// The simulator's network carries exactly these bytes, the fuzzers mutate them, and tests publish
/// hostile ones: every transport feeds the replicator the same decoded samples, which it checks in
/// one place (replication/validate.h).
///
/// Threading: every function here is pure and may be called from any thread.

#include <cstdint>
#include <span>
#include <vector>

#include "quiver/agents/replica/replication/messages.h"
#include "quiver/base/result.h"

namespace quiver::agents::inline replica {
class Replicator;
}  // namespace quiver::agents::inline replica

namespace quiver::agents::inline transport {

/// The topics, one per message kind.
enum class DdsTopic : std::uint8_t { kSummary, kDelta, kPull, kState, kBye };
inline constexpr std::size_t kDdsTopicCount = 5;
/// "quiver_summary", "quiver_delta", ...
/// @returns the static topic name. @pre `t` is one of the kDdsTopicCount enumerators.
const char* topic_name(DdsTopic t);
/// The topic of a message.
/// @returns the topic of `m`'s alternative. @pre `m` is not valueless_by_exception().
DdsTopic topic_of(const Message& m);

/// One serialized sample: its topic and its CDR bytes (the 4-byte encapsulation header, the body,
/// padding to a multiple of 4, as DDSI carries them).
struct CdrSample {
  DdsTopic topic = DdsTopic::kSummary;
  std::vector<std::uint8_t> bytes;
};

/// Serializes `s` as a sample of its topic, as a Cyclone writer does by default (XCDR1,
/// little-endian), or in another representation (XCDR version 1 or 2, either byte order) that a
/// writer may choose and a reader must accept.
/// @pre a DeltaMsg's payload and a StateMsg's chunk are not null. Any `xcdr_version` other than
///      2 means XCDR1.
/// @returns the topic and the bytes a Cyclone writer would put on the wire for `s`. Thread-safe.
CdrSample encode_cdr_sample(const Sample& s, int xcdr_version = 1, bool little_endian = true);

/// Decodes one serialized sample of `topic`: the 4-byte encapsulation header (XCDR1 or XCDR2,
/// either byte order; the only ones Cyclone accepts for these @final types) and the body, as
/// Cyclone 0.10.2 normalizes and reads it, but strict: a sample Cyclone 0.10's XCDR2 bound check
/// would let run past its end is refused.
/// @returns the Sample it carries, unchecked (the replicator validates it), or kMalformed /
/// kTruncated / kTooLarge naming the topic and what was wrong.
Result<Sample> decode_cdr_sample(DdsTopic topic, std::span<const std::uint8_t> bytes);

/// What a receiving transport does with serialized bytes: decodes them and hands the Sample to
/// `r` (Replicator::on_sample), or reports them as undecodable (Replicator::on_undecodable).
/// @pre called on `r`'s owner thread.
/// `now_ns` goes to Replicator::on_sample(). Errors are not returned: the replicator counts them.
void deliver_cdr_sample(Replicator& r, DdsTopic topic, std::span<const std::uint8_t> bytes, std::int64_t now_ns);

}  // namespace quiver::agents::inline transport
