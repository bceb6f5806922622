// The kinematic tree derived from RT claims: the replicated-tree move operation.
//
// Every child's register holds its latest move (claim); concurrent moves of one child are
// ordered by Lamport dot and the greatest wins. The tree is rebuilt by applying each child's
// winning move in Lamport order; a move whose parent is gone or that would close a cycle is
// skipped in favour of the parent the child had when the move was made (the "undo" of
// Kleppmann et al.), and if that fails too the child becomes a root. The result is a pure
// function of the replicated state, so every replica derives the same tree.

#include <algorithm>

#include "graph_impl.h"

namespace quiver::graph {

bool Graph::Impl::would_cycle(const NodeRec* parent, const NodeRec* child) const {
  // A leaf is nobody's ancestor: building a chain top-down never walks it.
  if (child->rt_children.empty()) return parent == child;
  for (const NodeRec* x = parent; x != nullptr; x = x->rt_parent)
    if (x == child) return true;
  return false;
}

void Graph::Impl::recompute_rt(std::vector<std::pair<NodeId, NodeId>>*) {
  rt_dirty = false;
  for (NodeRec* c : claimants) touch_rt(c);
  for (NodeRec* c : claimants)
    if (c->rt_parent) c->rt_parent->rt_children.clear();
  for (NodeRec* c : claimants) {
    c->rt_parent = nullptr;
    c->rt_epoch = Dot{};
  }

  struct Item {
    Dot order;
    NodeRec* child;
    const RtClaim* claim;
  };
  std::vector<Item> items;
  items.reserve(claimants.size());
  for (NodeRec* c : claimants) {
    if (!c->alive) continue;
    const auto* w = winner(c->claim);
    if (w) items.push_back(Item{w->dot, c, &w->value});
  }
  std::sort(items.begin(), items.end(),
            [](const Item& a, const Item& b) { return crdt::lamport_less(a.order, b.order); });

  auto usable = [&](NodeId pid, NodeRec* child) -> NodeRec* {
    NodeRec* p = find_node(pid);
    if (p == nullptr || !p->alive || would_cycle(p, child)) return nullptr;
    return p;
  };
  rt_skips = 0;
  rt_max_order = Dot{};
  for (const Item& it : items) {
    NodeRec* c = it.child;
    const RtClaim& cl = *it.claim;
    rt_max_order = it.order;
    c->rt_epoch = it.order;
    c->rt_base_pose = cl.pose;
    c->rt_base_stamp = cl.stamp;
    if (cl.parent.is_null()) continue;  // an explicit detach
    if (NodeRec* p = usable(cl.parent, c)) {
      c->rt_parent = p;
      p->rt_children.push_back(c);
      continue;
    }
    ++rt_skips;
    if (cl.fallback_parent.is_null()) continue;
    if (NodeRec* p = usable(cl.fallback_parent, c)) {
      c->rt_parent = p;
      c->rt_epoch = cl.fallback_epoch;
      c->rt_base_pose = cl.fallback_pose;
      c->rt_base_stamp = cl.fallback_stamp;
      p->rt_children.push_back(c);
    }
  }

}

void Graph::Impl::link_rt(NodeRec* c, NodeRec* parent) {
  if (c->rt_parent == parent) return;
  touch_rt(c);
  if (c->rt_parent) {
    auto& sib = c->rt_parent->rt_children;
    sib.erase(std::find(sib.begin(), sib.end(), c));
  }
  c->rt_parent = parent;
  if (parent) parent->rt_children.push_back(c);
}

void Graph::Impl::sync_claimant(NodeRec* c) {
  if (!c->claim.empty()) {
    claimants.insert(c);
    return;
  }
  claimants.erase(c);
  link_rt(c, nullptr);
  c->rt_epoch = Dot{};
  rt_dirty = true;
}

void Graph::Impl::claim_updated(NodeRec* c) {
  touch_rt(c);
  sync_claimant(c);
  const auto* w = winner(c->claim);
  if (rt_dirty || rt_skips != 0 || w == nullptr || !c->alive || !crdt::lamport_less(rt_max_order, w->dot)) {
    rt_dirty = true;
    return;
  }
  const RtClaim& cl = w->value;
  NodeRec* p = nullptr;
  if (!cl.parent.is_null()) {
    p = find_node(cl.parent);
    if (p == nullptr || !p->alive || would_cycle(p, c)) {
      rt_dirty = true;  // the full derivation decides between fallback and root
      return;
    }
  }
  link_rt(c, p);
  c->rt_epoch = w->dot;
  c->rt_base_pose = cl.pose;
  c->rt_base_stamp = cl.stamp;
  rt_max_order = w->dot;
}

RtEdge Graph::Impl::current_rt(const NodeRec& r) const {
  RtSample best{r.rt_base_stamp, r.rt_epoch, r.rt_epoch, r.rt_base_pose};
  for (const RtSample& s : r.history)
    if (s.epoch == r.rt_epoch && sample_less(best, s)) best = s;
  return RtEdge{r.rt_parent ? r.rt_parent->id : NodeId{}, r.id, best.pose, best.stamp, r.rt_epoch};
}

}  // namespace quiver::graph
