#pragma once
// Private: the hashes that key the frame table's name and id tables (KeyTable), shared by the
// readers that probe them and the owner that fills them.

#include <cstdint>
#include <string_view>

#include "quiver/base/hash.h"
#include "quiver/graph/ids.h"

namespace quiver::kinematics::internal {

inline std::uint64_t hash_name(std::string_view s) { return mix64(fnv1a64(s)); }

inline std::uint64_t hash_id(const graph::NodeId& id) {
  return mix64(hash_value(id.dot) + 0x51ed27ULL);
}

}  // namespace quiver::kinematics::internal
