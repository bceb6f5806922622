#pragma once
// The byte forms of what a store holds: log records and the snapshot, each ending in a checksum
// of everything before it, so that a damaged byte anywhere is found when it is read.

#include <array>
#include <cstdint>
#include <string>
#include <span>
#include <vector>

#include "quiver/crdt/causal_context.h"
#include "quiver/graph/ids.h"
#include "quiver/base/result.h"

namespace quiver::agents::inline replica::store {

enum class RecordKind : std::uint8_t { kDelta = 1, kState = 2, kSkipped = 3 };

struct Record {
  RecordKind kind = RecordKind::kDelta;
  graph::ReplicaId origin;               // kDelta, kSkipped
  std::uint64_t lo = 0, hi = 0;          // kDelta, kSkipped
  crdt::CausalContext applied;           // kState
  std::span<const std::uint8_t> payload;  // kDelta, kState: codec bytes (a view into the input)
};

std::vector<std::uint8_t> encode_delta_record(const graph::ReplicaId& origin, std::uint64_t lo, std::uint64_t hi,
                                              std::span<const std::uint8_t> payload);
std::vector<std::uint8_t> encode_state_record(const crdt::CausalContext& applied,
                                              std::span<const std::uint8_t> payload);
std::vector<std::uint8_t> encode_skipped_record(const graph::ReplicaId& origin, std::uint64_t lo, std::uint64_t hi);
/// `what` names the record in errors ("store /x: log record 12").
Result<Record> decode_record(std::span<const std::uint8_t> bytes, const std::string& what);

struct Snapshot {
  std::uint64_t upto = 0;  // the last log record it includes
  crdt::CausalContext applied;
  std::span<const std::uint8_t> state;  // codec bytes, kind kState (a view into the input)
};
std::vector<std::uint8_t> encode_snapshot(std::uint64_t upto, const crdt::CausalContext& applied,
                                          std::span<const std::uint8_t> state);
Result<Snapshot> decode_snapshot(std::span<const std::uint8_t> bytes, const std::string& what);

/// The checksum that ends every record and snapshot (of the bytes before it).
std::uint64_t record_checksum(std::span<const std::uint8_t> body);

/// A log key: the record number, big-endian, so that LMDB's byte order is numeric order.
std::array<std::uint8_t, 8> record_key(std::uint64_t n);
std::uint64_t record_number(std::span<const std::uint8_t> key);

}  // namespace quiver::agents::inline replica::store
