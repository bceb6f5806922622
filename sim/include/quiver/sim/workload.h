#pragma once
/// @file
/// Random graph churn: transactions of random changes (nodes and edges created and deleted,
/// attribute writes, RT moves and pose updates), drawn from one seeded generator.

#include <cstdint>
#include <string>

#include "quiver/graph/graph.h"
#include "quiver/base/rng.h"

namespace quiver::sim {

/// Relative weights of the change kinds, and sizes.
struct ChurnMix {
  int create_node = 6;
  int delete_node = 2;
  int set_attr = 10;
  int remove_attr = 1;
  int insert_edge = 5;
  int delete_edge = 2;
  int set_edge_attr = 2;
  int rt_move = 3;
  int rt_pose = 4;
  int rt_remove = 1;
  int max_ops_per_txn = 4;
  int max_nodes = 40;        ///< creation stops above this many visible nodes
  int shared_names = 4;      ///< a small pool of names that replicas race to create
  std::string spare_type;    ///< nodes of this type are never touched (empty: none)
};

/// Generates random transactions against a replica.
class Churn {
 public:
  explicit Churn(ChurnMix mix = {}) : mix_(mix) {}

  /// Builds and commits one random transaction on `g`; `now` is the virtual time (used as RT
  /// stamp). Returns the number of changes committed (0 if every draw was inapplicable).
  int step(graph::Graph& g, Rng& rng, std::int64_t now);

 private:
  ChurnMix mix_;
  std::uint64_t names_ = 0;
};

}  // namespace quiver::sim
