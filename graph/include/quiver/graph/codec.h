#pragma once
/// @file
/// Binary codec for GraphDelta (deltas, delta intervals, states and context diffs).
///
/// Format version 2 (all integers little-endian varints unless noted):
///   magic "QG", version u8, kind u8 (1 delta, 2 state), flags varint
///   [if flags & kSeq: sequence interval lo, hi - lo]
///   replica table: n, then n × (agent fixed64, incarnation varint); index 0 is the origin
///   symbol table: n, then n × string (attribute names, node and edge types)
///   context: n ranges × (replica index, lo, hi - lo)
///   [if flags & kImplicitDots: first counter F] added dots are then F, F+1, ... in stream order
///   nodes: n × node op; edges: n × edge op; [state: keep list]
/// See src/codec_format.h for the per-op layout. Decoding is bounds-checked throughout; any
/// malformed, truncated or oversized input yields an Error naming the field and byte offset, and
/// nothing is produced (not even a new entry in the process's table of names).
///
/// Beyond the syntax, a decoded message is checked against the limits table (limits.h) and the
/// meaning of its kind: every counter is at most crdt::kMaxCounter; names are non-empty UTF-8
/// within limits::kMaxNameBytes (node names without '~'); a delta (kDelta) changes something,
/// and every dot it adds, and every range of its context, is its origin's (a replica can only
/// mint its own dots), each added dot inside the context.

#include <cstdint>
#include <span>
#include <vector>

#include "quiver/graph/delta.h"
#include "quiver/graph/limits.h"
#include "quiver/base/result.h"

namespace quiver::graph {

/// Limits applied while decoding untrusted bytes: the table's (limits.h), tightened only by
/// tests.
struct DecodeLimits {
  std::uint64_t max_value_bytes = limits::kMaxValueBytes;  ///< one attribute value
  std::uint64_t max_name_bytes = limits::kMaxNameBytes;    ///< a symbol or node name
  std::uint64_t max_table = limits::kMaxTable;             ///< replicas or symbols per message
};

inline constexpr std::uint8_t kCodecVersion = 2;

/// Appends the encoding of `d` to `out`.
void encode(const GraphDelta& d, std::vector<std::uint8_t>& out);
/// The same, naming the sequence interval [seq_lo, seq_hi] in place of d's own.
void encode(const GraphDelta& d, std::vector<std::uint8_t>& out, std::uint64_t seq_lo, std::uint64_t seq_hi);
std::vector<std::uint8_t> encode(const GraphDelta& d);

/// Decodes into `out` (cleared first; its capacity is reused). On error `out` is unspecified
/// and the error names what was wrong and where.
Status decode(std::span<const std::uint8_t> in, GraphDelta& out, const DecodeLimits& limits = {});
Result<GraphDelta> decode(std::span<const std::uint8_t> in, const DecodeLimits& limits = {});

}  // namespace quiver::graph
