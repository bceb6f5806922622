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

std::size_t approx_size(const Message& m) {
  struct {
    std::size_t operator()(const SummaryMsg& s) { return 16 + s.name.size() + 24 * s.applied.size(); }
    std::size_t operator()(const DeltaMsg& d) { return 24 + d.payload->size(); }
    std::size_t operator()(const PullMsg& p) { return 16 + 24 * (p.applied.size() + p.context.size()); }
    std::size_t operator()(const StateMsg& s) { return 24 + s.chunk->size() + 24 * s.applied.size(); }
    std::size_t operator()(const ByeMsg&) { return 1; }
  } size;
  return std::visit(size, m);
}

const char* message_kind(const Message& m) {
  static constexpr const char* kNames[] = {"summary", "delta", "pull", "state", "bye"};
  return kNames[m.index()];
}

}  // namespace quiver::agents
