#pragma once
// The CRDT core benchmark (`quiver bench crdt`): random attribute writes on one replica, each
// delta encoded, then decoded and applied on another.

#include <cstdint>

namespace quiver::tools::bench {

struct CrdtBench {
  int nodes = 1000;          ///< nodes of the writing replica
  int attrs = 10;            ///< double attributes per node
  long updates = 1'000'000;  ///< random writes measured
  int batch = 100;           ///< writes per transaction
  std::uint64_t seed = 1;    ///< of the random writes
  bool events = false;       ///< subscribe to change events on the receiving replica
};

/// The workload we also run against Yjs and Automerge: replica A holds nodes × attrs doubles and
/// performs random writes in transactions of `batch`; every transaction's delta is encoded.
/// Replica B then decodes and applies every delta. Prints one JSON line on stdout (local and
/// remote rates, bytes per update, state size, whether the replicas ended equal).
/// @pre every count of `b` is at least 1.
/// @returns the exit status: 0 when the replicas end equal, 1 when they differ, 2 when a delta
/// cannot be decoded.
int run_crdt_bench(const CrdtBench& b);

}  // namespace quiver::tools::bench
