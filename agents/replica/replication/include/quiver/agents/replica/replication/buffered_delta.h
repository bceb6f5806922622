#pragma once
/// @file
/// The replicator's relay buffer, in part (private to Replicator): a buffered delta, and what
/// dropped deltas leave for the next ones.

#include <algorithm>
#include <cstdint>
#include <list>
#include <memory>
#include <vector>

#include "quiver/agents/replica/replication/transport.h"

namespace quiver::agents::inline replica {

/// A delta kept to answer pulls, and the record that tells a duplicate of it from an
/// equivocation (another payload under its (origin, lo)): its payload's digest and any other
/// version seen. The record lives as long as the delta is buffered.
struct BufferedDelta {
  /// A version seen under the same (origin, lo) besides the first (an equivocation), known by
  /// its interval's end and its payload's digest.
  struct Version {
    std::uint64_t hi = 0;
    std::uint64_t digest = 0;
    bool operator==(const Version&) const = default;
  };
  PeerId origin;
  std::uint64_t lo = 0, hi = 0;
  std::int64_t at_ns = 0;
  std::shared_ptr<const std::vector<std::uint8_t>> bytes;
  std::shared_ptr<const std::vector<std::uint8_t>> signature;
  std::uint64_t digest = 0;
  std::vector<Version> others;
  bool ours = false;  ///< `bytes` came from BufferSpares::bytes (our own delta): they go back there
  bool knows(std::uint64_t hi_, std::uint64_t d) const {
    return (hi == hi_ && digest == d) || std::find(others.begin(), others.end(), Version{hi_, d}) != others.end();
  }
};

/// What dropped deltas leave for the next ones (bounded; replicator_buffer.cc): list nodes, index
/// nodes and our own deltas' byte buffers. A delta like the last one then allocates nothing.
template <class Index>
struct BufferSpares {
  std::list<BufferedDelta> entries;
  std::vector<typename Index::node_type> index;
  std::vector<std::shared_ptr<std::vector<std::uint8_t>>> bytes;
};

}  // namespace quiver::agents
