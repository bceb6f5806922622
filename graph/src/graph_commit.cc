// Transaction commits: aborting, revalidating a stale transaction against the replica, and the
// commit itself (the changes applied, recorded as one delta and published).

#include <algorithm>
#include <unordered_map>
#include <unordered_set>

#include "quiver/graph/limits.h"

#include "graph_impl.h"
#include "transaction_book.h"

namespace quiver::graph {

void Transaction::abort() {
  release();
  ops_.clear();
  book_->reset(graph_->impl_->epoch);
}

Status Transaction::revalidate() const {
  // Replays every change on a fresh view of the replica: the same checks, in the same order.
  Transaction t(graph_);
  for (const TxnOp& op : ops_) {
    Status s;
    switch (op.kind) {
      case TxnOp::Kind::kCreateNode: {
        auto taken = graph_->find_node(op.name);
        if ((taken && !t.book_->deleted.count(*taken)) || t.book_->names.count(op.name))
          s = make_error(ErrorCode::kAlreadyExists, "create_node(): the name " + quote_name(op.name) + " is taken");
        t.book_->created.insert(op.node);
        t.book_->names.insert(op.name);
        break;
      }
      case TxnOp::Kind::kDeleteNode: s = t.delete_node(op.node); break;
      case TxnOp::Kind::kSetAttr: s = t.set(op.node, op.attr, op.value); break;
      case TxnOp::Kind::kRemoveAttr: {
        auto removed = t.remove_attr(op.node, op.attr);
        if (!removed.ok()) s = removed.error();
        break;
      }
      case TxnOp::Kind::kInsertEdge: s = t.insert_edge(op.node, op.other, op.type, op.attrs); break;
      case TxnOp::Kind::kDeleteEdge: s = t.delete_edge(op.node, op.other, op.type); break;
      case TxnOp::Kind::kSetEdgeAttr: s = t.set_edge_attr(EdgeKey{op.node, op.other, op.type}, op.attr, op.value); break;
      case TxnOp::Kind::kRemoveEdgeAttr: {
        auto removed = t.remove_edge_attr(EdgeKey{op.node, op.other, op.type}, op.attr);
        if (!removed.ok()) s = removed.error();
        break;
      }
      case TxnOp::Kind::kSetRt: s = t.set_rt(op.other, op.node, op.pose, op.stamp); break;
      case TxnOp::Kind::kRemoveRt: s = t.remove_rt(op.node); break;
    }
    if (!s.ok())
      return make_error(s.error().code, "commit(): a change no longer applies (another commit or a merge came first): " +
                                            s.error().message);
  }
  return {};
}

Result<CommitInfo> Transaction::commit() {
  Graph::Impl& g = *graph_->impl_;
  CommitInfo info;
  info.ops = ops_.size();
  if (ops_.empty()) return info;
  auto refuse = [&](Error e) -> Result<CommitInfo> {
    g.out.rule.clear();
    g.out.binding.clear();
    abort();
    return e;
  };
  // Another commit or a merge since this transaction's calls: check them again.
  const bool stale = book_->epoch != g.epoch;
  if (stale)
    if (Status s = revalidate(); !s.ok()) return refuse(s.error());
  if (g.permission_check) {
    Status s = g.permission_check(*graph_, ops_);
    if (!s.ok()) return refuse(s.error());
  }
  if (g.validator) {
    Status s = g.validator(*graph_, ops_);  // may annotate g.out with the rule it matched
    if (!s.ok()) return refuse(s.error());
  }
  // Every dot this commit may mint must fit below the counter limit: refuse rather than wrap.
  std::uint64_t dots = 0;
  for (const TxnOp& op : ops_) dots += 2 + op.attrs.size();
  if (!g.can_mint(dots))
    return refuse(make_error(ErrorCode::kTooLarge, "commit(): this replica's counter space is exhausted"));
  // Attribute writes on distinct registers commute: order each run of them by register so the
  // delta groups writes per node (smaller encoding, fewer node records touched).
  std::vector<std::uint32_t>& order = g.commit_order;
  order.resize(ops_.size());
  for (std::uint32_t i = 0; i < order.size(); ++i) order[i] = i;
  for (std::size_t i = 0; i < ops_.size();) {
    std::size_t j = i;
    while (j < ops_.size() && ops_[j].kind == TxnOp::Kind::kSetAttr) ++j;
    if (j - i > 1)
      std::stable_sort(order.begin() + i, order.begin() + j, [this](std::uint32_t x, std::uint32_t y) {
        const TxnOp& a = ops_[x];
        const TxnOp& b = ops_[y];
        if (a.node != b.node) return a.node < b.node;
        return text_less(a.attr, b.attr);
      });
    i = j + 1;
  }
  // Records found while validating are still valid if nothing merged or committed since.
  std::vector<const void*>& hints = book_->hints;
  hints.resize(ops_.size());
  ++g.epoch;
  g.begin_tracking();
  if (g.out.nodes.empty() && g.out.edges.empty()) {
    g.out.kind = GraphDelta::Kind::kDelta;
    g.out.origin = g.self;
  }
  // This transaction's node ids are about to be published: no longer reserved.
  g.unreserve(book_->reserved);
  book_->reserved.clear();
  // Large transactions: grow the outgoing delta and the indexes once rather than step by step
  // (each step copies, and on a fresh heap every byte copied is a page to fault in).
  if (ops_.size() > 64) {
    g.out.nodes.reserve(g.out.nodes.size() + 2 * ops_.size());
    g.out.claims.reserve(g.out.claims.size() + ops_.size());
    g.out.samples.reserve(g.out.samples.size() + ops_.size());
  }
  if (book_->created.size() > 64) {
    const std::size_t more = book_->created.size();
    g.nodes.reserve(g.nodes.size() + more);
    g.by_name.reserve(g.by_name.size() + more);
    g.claimants.reserve(g.claimants.size() + more);
    g.claim_parent_refs.reserve(g.claim_parent_refs.size() + more);
  }
  // What the nodes and edges this transaction deletes held before it (their deletion events carry
  // it), saved before any of its writes.
  if (g.tracker.enabled)
    for (const TxnOp& op : ops_) {
      if (op.kind == TxnOp::Kind::kDeleteNode) {
        if (NodeRec* n = g.find_node(op.node)) g.save_last(n);
      } else if (op.kind == TxnOp::Kind::kDeleteEdge) {
        if (EdgeRec* e = g.find_edge(EdgeKey{op.node, op.other, op.type})) g.save_last(*e);
      }
    }
  for (std::uint32_t k : order) {
    TxnOp& op = ops_[k];
    NodeRec* n = !stale && hints[k] ? const_cast<NodeRec*>(static_cast<const NodeRec*>(hints[k])) : g.find_node(op.node);
    bool alive = n && n->alive;
    switch (op.kind) {
      case TxnOp::Kind::kCreateNode:
        g.local_create_node(op.node, op.type, op.name, op.attrs);
        break;
      case TxnOp::Kind::kDeleteNode:
        if (alive) g.local_delete_node(n);
        break;
      case TxnOp::Kind::kSetAttr:
        if (alive) g.local_write_attr(n, op.attr, std::move(op.value));
        break;
      case TxnOp::Kind::kRemoveAttr:
        if (alive) g.local_remove_attr(n, op.attr);
        break;
      case TxnOp::Kind::kInsertEdge:
        if (alive && g.visible_node(op.other)) g.local_insert_edge(EdgeKey{op.node, op.other, op.type}, op.attrs);
        break;
      case TxnOp::Kind::kDeleteEdge:
        if (EdgeRec* e = g.find_edge(EdgeKey{op.node, op.other, op.type})) g.local_delete_edge(e);
        break;
      case TxnOp::Kind::kSetEdgeAttr:
      case TxnOp::Kind::kRemoveEdgeAttr: {
        EdgeRec* e = g.find_edge(EdgeKey{op.node, op.other, op.type});
        if (e && g.edge_visible(*e))
          g.local_write_edge_attr(e, op.attr, op.kind == TxnOp::Kind::kSetEdgeAttr ? &op.value : nullptr);
        break;
      }
      case TxnOp::Kind::kSetRt: {
        NodeRec* p = g.find_node(op.other);
        if (alive && p && p->alive) g.local_set_rt(p, n, op.pose, op.stamp);
        break;
      }
      case TxnOp::Kind::kRemoveRt:
        if (alive) g.local_remove_rt(n);
        break;
    }
  }
  // A commit whose changes all turned out to be no-ops publishes nothing (a delta always changes
  // something); counters it skipped go out with the next commit that does.
  const bool changed = !g.out.nodes.empty() || !g.out.edges.empty();
  if (changed) g.publish_own_dots(info);
  if (g.rt_dirty) g.recompute_rt(nullptr);
  abort();  // the transaction is spent
  if (g.sink && changed) g.sink(g.out);
  g.out.clear();
  g.finish_tracking(true, g.self, nullptr);
  return info;
}

}  // namespace quiver::graph
