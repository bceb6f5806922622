#pragma once
/// @file
/// Byte packets for envelopes (docs/protocol.md): used by the simulator, byte-oriented transports
/// and the fuzzers. Decoding is bounds-checked and never trusts a length or a count.

#include <cstdint>
#include <span>
#include <vector>

#include "quiver/agents/replica/replication/messages.h"
#include "quiver/base/result.h"

namespace quiver::agents::inline replica {

inline constexpr std::uint8_t kPacketVersion = 2;

void encode_packet(const Envelope& e, std::vector<std::uint8_t>& out);
std::vector<std::uint8_t> encode_packet(const Envelope& e);
/// Decodes a packet; the error names the field and byte offset of the first problem.
Result<Envelope> decode_packet(std::span<const std::uint8_t> packet);

}  // namespace quiver::agents
