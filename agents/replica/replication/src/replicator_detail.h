#pragma once
// Private: how the Replicator names and fingerprints what it relays: a payload's digest and the
// text of an (origin, seq) interval, for its messages.

#include <cstdint>
#include <string>
#include <vector>

#include "quiver/agents/replica/replication/replicator.h"

namespace quiver::agents::inline replica::internal {

inline std::uint64_t digest_of(const std::vector<std::uint8_t>& bytes) {
  Hasher h(0xde17a);
  h.bytes(bytes.data(), bytes.size());
  return h.h64();
}

inline std::string interval(const PeerId& origin, std::uint64_t lo, std::uint64_t hi) {
  return "(" + origin.to_string() + ", " + std::to_string(lo) + (hi == lo ? "" : ".." + std::to_string(hi)) + ")";
}

}  // namespace quiver::agents::inline replica::internal
