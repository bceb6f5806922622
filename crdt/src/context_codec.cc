// The wire form of a causal context and of a replica id, and their bounds-checked decoding.
#include "quiver/crdt/context_codec.h"

namespace quiver::crdt {

void encode_replica(const ReplicaId& id, bytes::Writer& w) {
  w.fixed64(id.agent);
  w.varint(id.incarnation);
}

ReplicaId decode_replica(bytes::Reader& r, const char* field) {
  ReplicaId id;
  id.agent = r.fixed64(field);
  id.incarnation = r.varint(field);
  return id;
}

void encode_context(const CausalContext& c, bytes::Writer& w) {
  std::vector<ReplicaId> reps = c.replicas();
  w.varint(reps.size());
  // Ranges come out grouped by replica in ascending order: emit them per replica.
  std::size_t i = 0;
  std::vector<CausalContext::Range> ranges;
  auto flush = [&](const ReplicaId& r) {
    encode_replica(r, w);
    w.varint(ranges.size());
    std::uint64_t prev = 0;
    for (const auto& rg : ranges) {
      w.varint(rg.lo - prev);
      w.varint(rg.hi - rg.lo);
      prev = rg.hi;
    }
    ranges.clear();
  };
  c.for_each_range([&](const ReplicaId& r, std::uint64_t lo, std::uint64_t hi) {
    if (!ranges.empty() && !(reps[i] == r)) {
      flush(reps[i]);
      ++i;
    }
    ranges.push_back({lo, hi});
  });
  if (!ranges.empty()) flush(reps[i]);
}

void decode_context(bytes::Reader& r, CausalContext& out, std::uint64_t max_replicas, std::uint64_t max_ranges) {
  out.clear();
  std::uint64_t n = r.count("context replica count", max_replicas, 10);
  std::uint64_t total = 0;
  for (std::uint64_t i = 0; i < n && r.ok(); ++i) {
    ReplicaId id = decode_replica(r, "context replica");
    std::uint64_t k = r.count("context range count", max_ranges, 2);
    total += k;
    if (total > max_ranges) {
      r.fail(ErrorCode::kTooLarge, "context range count", "too many ranges");
      return;
    }
    std::uint64_t prev = 0;
    for (std::uint64_t j = 0; j < k && r.ok(); ++j) {
      std::uint64_t gap = r.varint("context range gap");
      std::uint64_t len = r.varint("context range length");
      std::uint64_t lo = prev + gap;
      if (!r.ok()) return;
      if (lo < prev || lo == 0 || (j > 0 && gap == 0) || lo + len < lo) {
        r.fail(ErrorCode::kMalformed, "context range", "ranges must be ascending, disjoint and nonzero");
        return;
      }
      out.add_range(id, lo, lo + len);
      prev = lo + len;
    }
  }
}

}  // namespace quiver::crdt
