#pragma once
/// @file
/// Binary codec for GraphDelta (deltas, delta intervals, states and context diffs).
///
/// Format version 1 (all integers little-endian varints unless noted):
///   magic "QG", version u8, kind u8 (1 delta, 2 state), flags varint
///   replica table: n, then n × (agent fixed64, incarnation varint); index 0 is the origin
///   symbol table: n, then n × string (attribute names, node and edge types)
///   context: n ranges × (replica index, lo, hi - lo)
///   [if flags & kImplicitDots: first counter F] added dots are then F, F+1, ... in stream order
///   nodes: n × node op; edges: n × edge op; [state: keep list]
/// See codec.cc for the per-op layout. Decoding is bounds-checked throughout; any malformed,
/// truncated or oversized input yields an Error naming the field and byte offset, and nothing
/// is produced.

#include <cstdint>
#include <span>
#include <vector>

#include "quiver/graph/delta.h"
#include "quiver/result.h"

namespace quiver::graph {

/// Limits applied while decoding untrusted bytes.
struct DecodeLimits {
  std::uint64_t max_value_bytes = 64ull << 20;  ///< one attribute value
  std::uint64_t max_name_bytes = 4096;          ///< a symbol or node name
  std::uint64_t max_table = 1u << 16;           ///< replicas or symbols per message
};

inline constexpr std::uint8_t kCodecVersion = 1;

/// Appends the encoding of `d` to `out`.
void encode(const GraphDelta& d, std::vector<std::uint8_t>& out);
std::vector<std::uint8_t> encode(const GraphDelta& d);

/// Decodes into `out` (cleared first; its capacity is reused). On error `out` is unspecified
/// and the error names what was wrong and where.
Status decode(std::span<const std::uint8_t> in, GraphDelta& out, const DecodeLimits& limits = {});
Result<GraphDelta> decode(std::span<const std::uint8_t> in, const DecodeLimits& limits = {});

}  // namespace quiver::graph
