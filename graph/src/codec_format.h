#pragma once
// Private: the GraphDelta codec's wire format, shared by the encoder and the decoder.
//
// Node op:  hdr varint = attr_count << 5 | flags (1 header, 2 removed, 4 claims, 8 samples,
//           16 replica differs from the previous node's), [replica index], counter (delta from
//           the previous node of that replica: unsigned when the message is sorted, else
//           zigzag; absolute after a replica change), [header: type symbol, name],
//           [no header, message flag kTyped: type symbol + 1, 0 for none],
//           attr ops, [claims: removed dots, added claims], [samples]
// Attr op:  hdr varint = symbol << 2 | code
//           code 0: one value whose dot is the origin's; overwrites one origin dot (gap varint)
//           code 1: one value (origin dot), removes nothing
//           code 2: general: removed dots, then values with explicit dots
//           code 3: removes dots only
// Edge op:  from, to (node refs), type symbol, flags (1 removed, 2 added, 4 attrs), lists.
// "Origin dot" = the next implicit dot when the message has kImplicitDots, else an offset
// (varint) from the origin's lowest context counter.

#include <cstddef>
#include <cstdint>

namespace quiver::graph::internal {

inline constexpr std::uint8_t kMagic0 = 'Q';
inline constexpr std::uint8_t kMagic1 = 'G';
// Message flags.
inline constexpr std::uint64_t kImplicitDots = 1, kSortedNodes = 2, kFenced = 4, kClaim = 8, kSeq = 16, kTyped = 32;
inline constexpr std::uint64_t kAllFlags = 63;
// Decoded symbols not yet in the process's table are provisional (this bit set, the low bits
// index the message's table) until the whole message has been read and checked: a message that
// fails adds nothing to the table.
inline constexpr std::uint32_t kProvisional = 0x80000000u;
// Node op flags.
inline constexpr std::uint64_t kHdr = 1, kRemoved = 2, kClaims = 4, kSamples = 8, kReplicaSwitch = 16;
// Edge op flags.
inline constexpr std::uint64_t kEdgeRemoved = 1, kEdgeAdded = 2, kEdgeAttrs = 4;
// Attribute op codes.
inline constexpr std::uint64_t kOverwrite = 0, kFresh = 1, kGeneral = 2, kRemoveOnly = 3;

inline std::uint32_t u32(std::size_t n) { return static_cast<std::uint32_t>(n); }

}  // namespace quiver::graph::internal
