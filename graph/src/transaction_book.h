#pragma once
// Private: a transaction's bookkeeping (Transaction::Book), shared by its calls and its commit.

#include <cstdint>
#include <optional>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "quiver/graph/graph.h"
#include "small_index.h"

namespace quiver::graph {

/// A map that is a short vector (emptying it keeps its capacity, so refilling it allocates
/// nothing), found through a SmallIndex.
template <class K, class V>
class SmallMap {
 public:
  V* find(const K& k) {
    const std::size_t i = index_.find(k, items_.size(), [this](std::size_t j) { return items_[j].first; });
    return i == SmallIndex<K>::npos ? nullptr : &items_[i].second;
  }
  const V* find(const K& k) const { return const_cast<SmallMap*>(this)->find(k); }
  bool contains(const K& k) const { return find(k) != nullptr; }
  V& operator[](const K& k) {
    if (V* v = find(k)) return *v;
    items_.emplace_back(k, V{});
    index_.added(k, items_.size(), [this](std::size_t j) { return items_[j].first; });
    return items_.back().second;
  }
  void reserve(std::size_t n) { items_.reserve(n); }
  std::size_t size() const { return items_.size(); }
  void clear() {
    items_.clear();
    index_.clear();
    if (items_.capacity() > kKeep) items_ = {};
  }

 private:
  static constexpr std::size_t kKeep = 64;
  std::vector<std::pair<K, V>> items_;
  SmallIndex<K> index_;
};

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
  SmallMap<EdgeKey, bool> edges;              // symbolic edges inserted (true) or deleted here
  SmallMap<NodeId, std::optional<NodeId>> parent;  // RT parent after this txn's moves
  SmallMap<NodeId, bool> parents;             // nodes that gained an RT child here
  std::vector<TxnOp> spare_ops;               // the ops' capacity while the book waits in the graph

  /// Empties the book for another transaction, keeping what is small enough to be worth keeping:
  /// a transaction like the last one then allocates nothing for its bookkeeping.
  void reset(std::uint64_t at_epoch) {
    epoch = at_epoch;
    open = false;
    bytes = 0;
    hints.clear();
    reserved.clear();
    clear_small(created);
    clear_small(deleted);
    clear_small(names);
    edges.clear();
    parent.clear();
    parents.clear();
  }

 private:
  // Clearing a hash container costs its bucket count: one a large transaction grew is dropped.
  template <class C>
  static void clear_small(C& c) {
    if (c.bucket_count() > 64) c = C{};
    else c.clear();
  }
};

}  // namespace quiver::graph
