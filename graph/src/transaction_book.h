#pragma once
// Private: a transaction's bookkeeping (Transaction::Book), shared by its calls and its commit.

#include <cstdint>
#include <optional>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "quiver/graph/graph.h"

namespace quiver::graph {

/// A transaction's bookkeeping: what it created, deleted and moved so far, for O(1) checks.
struct Transaction::Book {
  std::uint64_t epoch = 0;     // the graph's epoch its view was taken at
  bool open = false;           // counted in Graph::Impl::open_transactions
  std::uint64_t bytes = 0;     // estimated encoding of the delta
  std::vector<const void*> hints;             // node records found while validating, per op
  std::vector<std::uint64_t> reserved;        // counters handed out as node ids
  std::unordered_set<NodeId> created;
  std::unordered_set<NodeId> deleted;
  std::unordered_set<std::string> names;      // names taken by create_node
  std::unordered_map<EdgeKey, bool> edges;    // symbolic edges inserted (true) or deleted here
  std::unordered_map<NodeId, std::optional<NodeId>> parent;  // RT parent after this txn's moves
  std::unordered_set<NodeId> parents;         // nodes that gained an RT child here
};

}  // namespace quiver::graph
