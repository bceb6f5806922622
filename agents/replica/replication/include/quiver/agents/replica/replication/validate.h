#pragma once
/// @file
/// The one check of everything a peer sends, whatever carried it: every transport (Cyclone DDS,
/// the simulator's network, the fuzzers) decodes the same CDR samples and hands them to
/// Replicator::on_sample(), which calls validate() before it uses anything. What passes is well-formed and bounded:
/// counts, sizes and ranges are within the limits below, counters within crdt::kMaxCounter, no
/// range has lo = 0 or hi < lo. What fails is refused whole, with an error naming the sender, the
/// message, the field and the value.

#include <cstdint>
#include <functional>
#include <string>

#include "quiver/agents/replica/replication/messages.h"
#include "quiver/graph/limits.h"
#include "quiver/base/result.h"

namespace quiver::agents::inline replica {

struct SampleLimits {
  std::size_t max_ranges = 1u << 16;        ///< ranges in one range list
  std::size_t max_name_bytes = 1024;        ///< an agent's name in a summary
  std::uint64_t max_interval = 1u << 20;    ///< sequence numbers one delta interval covers
  std::size_t max_payload_bytes = graph::limits::kMaxDeltaBytes + (1u << 20);  ///< one delta
  std::size_t max_chunk_bytes = 16u << 20;  ///< one state chunk
  std::uint64_t max_chunks = 1u << 16;      ///< chunks of one state transfer
  std::size_t max_signature_bytes = 512;    ///< a delta's signature
  std::size_t max_rumors = 32;              ///< membership rumors one beat carries
};

/// Checks a sample against `limits`. Pure and thread-safe; payloads are not decoded here (the
/// replicator decodes a delta's payload after this check).
/// `who`, if given, names the sender in errors (a replicator: "'speech' (<id>)"); else its id. It
/// is called only for a refused sample.
/// @returns kMalformed or kTooLarge naming the sender, the message kind, the field and the value.
///          kMalformed: a null sender or origin, a range or interval with lo = 0, hi < lo or a
///          counter above crdt::kMaxCounter, an empty payload or chunk, a chunk index out of
///          range, a name not UTF-8. kTooLarge: a count or size over `limits`.
Status validate(const Sample& s, const SampleLimits& limits = {},
                const std::function<std::string(const PeerId&)>& who = {});

}  // namespace quiver::agents
