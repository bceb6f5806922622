#pragma once
// The durable store benchmark (`quiver bench store`, docs/persistence.md): the write rate
// without and with a store under each durability, and the reload time of a large replica.

#include <string>

namespace quiver::tools::bench {

struct StoreBench {
  int nodes = 1000;            ///< nodes of the written replica
  int attrs = 10;              ///< double attributes per node
  long updates = 1'000'000;    ///< random writes per run
  int batch = 100;             ///< writes per transaction
  int runs = 3;                ///< rounds (medians are reported)
  int reload_nodes = 100'000;  ///< nodes of the reloaded replica
  std::string dir;  ///< where stores are made (empty: a new folder in /tmp, removed after)
};

/// What the durable store costs:
///  - write: the `bench crdt` workload (random attribute writes in transactions, each delta
///    encoded) with no store and with a store under each durability, side by side in one run;
///    the figure is the local write rate, as in `bench crdt`, and the store's final flush.
///  - reload: a replica of `reload_nodes` nodes in a store (as a log of transactions, then as a
///    snapshot), reopened and loaded into a new graph: medians of several runs.
/// Prints one JSON line per durability and one per reload form on stdout.
/// @pre every count of `b` is at least 1.
/// @returns the exit status: 0, 1 when the reload does not give back every node, 2 when a store
/// cannot be made, written or reopened.
int run_store_bench(const StoreBench& b);

}  // namespace quiver::tools::bench
