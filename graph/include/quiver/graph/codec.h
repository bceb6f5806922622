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
///
/// Threading: every function here is thread-safe on distinct arguments (the table of names it
/// interns into is thread-safe). Errors are returned as values; nothing throws on bad input.

#include <cstdint>
#include <functional>
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
/// @pre `d`'s spans index its own arrays (as a Graph or decode() builds it), and d.seq_lo <=
///      d.seq_hi unless d.seq_lo is 0 (unbound). A fragment that breaks the checks listed above
///      still encodes, but decode() refuses it.
void encode(const GraphDelta& d, std::vector<std::uint8_t>& out);
/// The same, naming the sequence interval [seq_lo, seq_hi] in place of d's own.
/// @pre as above, for these seq_lo and seq_hi.
void encode(const GraphDelta& d, std::vector<std::uint8_t>& out, std::uint64_t seq_lo, std::uint64_t seq_hi);
/// @returns the encoding of `d` in a new buffer. @pre as above.
std::vector<std::uint8_t> encode(const GraphDelta& d);

/// Which ops a state's parts hold in one pass of encode_parts(): both, node ops only, or edge
/// ops only (the other kind may be left out of the parts).
enum class PartOps { kAll, kNodes, kEdges };
/// Calls its second argument with each part of one state in order, the same parts on every call:
/// kState fragments of one origin and context whose ops together are the state's, the keep list
/// spread over them. At least one part, if only an empty one.
using PartSource = std::function<void(PartOps, const std::function<void(const GraphDelta& part)>&)>;
/// Appends the encoding of the state whose parts `parts` gives, as one message (decode() reads
/// it whole, decode_parts() in parts): a state of megabytes is never held as one GraphDelta.
/// encode_state() (state_parts.h) is the source it was made for.
void encode_parts(const PartSource& parts, std::vector<std::uint8_t>& out);

/// Decodes into `out` (cleared first; its capacity is reused). On error `out` is unspecified
/// and the error names what was wrong and where.
/// @returns kMalformed (bad magic, kind, flags or structure; a check above fails), kTruncated
///          (input ends early), kTooLarge (a count or length over `limits`, or the table of
///          names is full), kUnsupportedVersion (another format version).
Status decode(std::span<const std::uint8_t> in, GraphDelta& out, const DecodeLimits& limits = {});
/// The same into a new GraphDelta. @returns the fragment or decode()'s error.
Result<GraphDelta> decode(std::span<const std::uint8_t> in, const DecodeLimits& limits = {});

/// Receives one part of a state decoded in parts; an error stops the decoding and is returned.
using PartSink = std::function<Status(const GraphDelta& part)>;
/// Decodes a state (kind kState) a part at a time, into `scratch`: `part` sees at most
/// `part_ops` node and edge ops (with their attributes, values, claims and samples), each part
/// the message's context, and the last part the rest and the keep list. The whole message is
/// checked as decode() checks it, but the checks of its end come after the earlier parts went
/// to `part`, and a symbol new to this process is provisional in those parts: decode the
/// message once with a sink that keeps nothing before acting on its parts (merge_state() in
/// state_parts.h does). So a state of megabytes is never held decoded at once.
/// @returns decode()'s errors, kMalformed for a delta, or the first error of `part`.
Status decode_parts(std::span<const std::uint8_t> in, GraphDelta& scratch, std::size_t part_ops, const PartSink& part,
                    const DecodeLimits& limits = {});
}  // namespace quiver::graph
