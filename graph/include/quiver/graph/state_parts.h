#pragma once
/// @file
/// States in parts: a replica's state encoded from its records, and an encoded state joined
/// into a replica, a few hundred ops at a time. A state of megabytes (a late joiner's world, a
/// store's snapshot) is then never held as one decoded GraphDelta on either side, and memory
/// touched for the first time is most of what a large state transfer costs.
///
/// Threading: the graph's owner thread only (as every Graph member).

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "quiver/crdt/causal_context.h"
#include "quiver/graph/codec.h"
#include "quiver/graph/graph.h"

namespace quiver::graph {

/// Appends the encoding of g.state_diff(theirs) to `out` (an empty `theirs`: the whole state),
/// built from g's records in parts of at most `part_ops` node and edge ops (encode_parts()).
/// The bytes decode as the encoding of state_diff(theirs) does.
void encode_state(const Graph& g, const crdt::CausalContext& theirs, std::vector<std::uint8_t>& out,
                  std::size_t part_ops = 256);

/// Joins an encoded state (kState, codec bytes) into `g`: the same as decode() and g.merge(),
/// part by part (decode_parts(): at most `part_ops` node and edge ops at a time in `scratch`,
/// whose capacity is reused). Nothing is joined unless the whole message decodes and `admit`
/// (if set) accepts every part. With merge observers, which see whole fragments, the state is
/// decoded whole and merged.
/// @returns decode()'s errors, kMalformed for a delta, or `admit`'s first error.
Status merge_state(Graph& g, std::span<const std::uint8_t> encoded, GraphDelta& scratch, const PartSink& admit = {},
                   const DecodeLimits& limits = {}, std::size_t part_ops = 256);

}  // namespace quiver::graph
