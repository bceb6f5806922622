// The replication protocol's messages as transports carry them: contexts to and from range lists, and the name
// of each message kind.
#include "quiver/agents/replica/replication/messages.h"

#include <type_traits>

namespace quiver::agents::inline replica {

RangeList to_ranges(const crdt::CausalContext& c) {
  RangeList out;
  out.reserve(c.range_count());
  c.for_each_range([&](const PeerId& r, std::uint64_t lo, std::uint64_t hi) { out.push_back(Range{r, lo, hi}); });
  return out;
}

crdt::CausalContext to_context(const RangeList& r) {
  crdt::CausalContext c;
  for (const Range& x : r) c.add_range(x.replica, x.lo, x.hi);
  return c;
}

const char* message_kind(const Message& m) {
  static constexpr const char* kNames[] = {"summary", "delta", "pull", "state", "bye"};
  return kNames[m.index()];
}

}  // namespace quiver::agents
