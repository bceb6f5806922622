#pragma once
// Private: how the Replicator fingerprints what it relays: a payload's digest.

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

}  // namespace quiver::agents::inline replica::internal
