#pragma once
// The structural changes a transaction (or an incoming delta) makes to the state it starts
// from: nodes created, deleted and retyped, edges added and removed, and the first change that
// needs an `allow` line the grammar lacks.

#include <map>
#include <set>
#include <string>
#include <vector>

#include "quiver/agents/rules/grammar/grammar.h"

namespace quiver::agents::inline rules::internal {

struct Changes {
  std::map<graph::NodeId, std::string> created;  // id -> type
  std::set<graph::NodeId> deleted;
  /// Nodes that changed type, id -> new type. The graph cannot retype a node: a retype is a
  /// replacement, the node deleted and a node of the new type created under the same name in
  /// one change, taking over the old one's edges. The new node is read as the old id.
  std::map<graph::NodeId, std::string> retyped;
  std::vector<graph::EdgeKey> added, removed;
  std::string unruled;  // first change that needs an 'allow' the grammar lacks
  // Notes `what()` as the unruled change unless `ok` (first: an allowed change builds no message
  // and looks nothing up) or one is noted already.
  template <class What>
  void need(bool ok, const What& what) {
    if (!ok && unruled.empty()) unruled = what();
  }
  bool structural() const {
    return !created.empty() || !deleted.empty() || !retyped.empty() || !added.empty() ||
           !removed.empty();
  }
};

/// The changes of a pending transaction `ops` to `g`.
Changes extract(const Grammar& gr, const graph::Graph& g, const std::vector<graph::TxnOp>& ops);
/// The changes a delta makes to `g` (the receiver's state before merging it).
Changes extract_delta(const Grammar& gr, const graph::Graph& g, const graph::GraphDelta& d);

/// "create a mug, delete cup, retype x to table, remove robot -[in]-> kitchen, add ...".
std::string describe(const graph::Graph& g, const Changes& c);
/// "robot -[in]-> kitchen" (a node the change creates: "new TYPE").
std::string describe(const graph::Graph& g, const graph::EdgeKey& e,
                     const std::map<graph::NodeId, std::string>& created);

}  // namespace quiver::agents::inline rules::internal
