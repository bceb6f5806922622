// Joining remote deltas and states into the replica.
//
// A delta (kDelta) lists every dot it removes under the key it removed it from, so the join
// visits only the delta's keys: at each key, local entries whose dots the delta removes go, and
// delta entries whose dots this replica has never seen come in. A state (kState) carries the
// sender's whole context instead; its join scans the local store once: a local entry whose dot
// the sender has seen but no longer holds was removed there.

#include <unordered_set>

#include "graph_impl.h"

namespace quiver::graph {

void Graph::Impl::merge_register(AttrList& attrs, const GraphDelta& d, const GraphDelta::AttrOp& a) {
  AttrSlot* slot = find_slot(attrs, a.name);
  if (slot)
    for (std::uint32_t i = a.removed.begin; i < a.removed.end; ++i) slot->reg.erase(d.removed[i]);
  for (std::uint32_t i = a.added.begin; i < a.added.end; ++i) {
    const auto& e = d.values[i];
    if (ctx.contains(e.dot)) continue;
    if (slot == nullptr) {
      attrs.push_back(AttrSlot{a.name, {}});
      slot = &attrs.back();
    }
    slot->reg.insert(e.dot, e.value, e.fence);
  }
  if (slot && slot->reg.empty()) attrs.erase(attrs.begin() + (slot - attrs.data()));
}

void Graph::Impl::merge_ops(const GraphDelta& d) {
  // A large fragment (a state transfer, a reload) grows the tables once, not by rehashing.
  if (d.nodes.size() > 1024) nodes.reserve(nodes.size() + d.nodes.size());
  if (d.edges.size() > 1024) edges.reserve(edges.size() + d.edges.size());
  for (const GraphDelta::NodeOp& op : d.nodes) {
    if (is_dead(op.id)) continue;  // nothing can touch a deleted node again
    NodeRec* r = find_node(op.id);
    if (op.has_header && !(r && r->alive) && !ctx.contains(op.id.dot)) {
      r = &node_record(op.id);
      touch_node(r);
      touch_incident_edges(r);
      set_alive(r, true, op.type, op.name);
    }
    // A record's attribute list grows to the op's count at once, not by doubling (a joiner's
    // ten attributes take ten slots, not sixteen: a third less memory to touch).
    if (r != nullptr && r->attrs.empty()) r->attrs.reserve(op.attrs.size());
    for (std::uint32_t i = op.attrs.begin; i < op.attrs.end; ++i) {
      const auto& a = d.attrs[i];
      if (r == nullptr) {
        if (a.added.empty()) continue;
        r = &node_record(op.id);
        r->attrs.reserve(op.attrs.end - i);
      }
      touch_attr(r, a.name);
      merge_register(r->attrs, d, a);
    }
    if (!op.claim_removed.empty() || !op.claim_added.empty()) {
      if (r == nullptr && !op.claim_added.empty()) r = &node_record(op.id);
      if (r != nullptr) {
        bool changed = false;
        r->claim.erase_if([&](const crdt::Entry<RtClaim>& e) {
          for (std::uint32_t i = op.claim_removed.begin; i < op.claim_removed.end; ++i)
            if (d.removed[i] == e.dot) {
              index_claim_entry(e.value, -1);
              changed = true;
              return true;
            }
          return false;
        });
        for (std::uint32_t i = op.claim_added.begin; i < op.claim_added.end; ++i) {
          const auto& e = d.claims[i];
          if (ctx.contains(e.dot) || r->claim.find(e.dot)) continue;
          r->claim.insert(e.dot, e.value);
          index_claim_entry(e.value, +1);
          changed = true;
        }
        if (changed) claim_updated(r);
      }
    }
    for (std::uint32_t i = op.samples.begin; i < op.samples.end; ++i) {
      const RtSample& s = d.samples[i];
      if (ctx.contains(s.dot)) continue;
      if (r == nullptr) r = &node_record(op.id);
      insert_sample(r, s);
    }
    if (op.removed) pending_kills.push_back(op.id);
    if (r) gc_candidates.push_back(op.id);
  }

  for (const GraphDelta::EdgeOp& op : d.edges) {
    if (is_dead(op.key.from) || is_dead(op.key.to)) continue;
    EdgeRec* e = find_edge(op.key);
    if (e == nullptr) {
      bool adds = !op.added.empty();
      for (std::uint32_t i = op.attrs.begin; i < op.attrs.end && !adds; ++i) adds = !d.attrs[i].added.empty();
      if (!adds) continue;
      e = &edge_record(op.key);
    }
    if (!op.removed.empty()) save_last(*e);
    touch_edge(*e);
    if (!op.removed.empty() || !op.added.empty()) touch_edge_version(*e);
    for (std::uint32_t i = op.removed.begin; i < op.removed.end; ++i) e->exists.erase(d.removed[i]);
    for (std::uint32_t i = op.added.begin; i < op.added.end; ++i)
      if (!ctx.contains(d.added[i])) e->exists.insert(d.added[i]);
    for (std::uint32_t i = op.attrs.begin; i < op.attrs.end; ++i) {
      touch_edge_attr(*e, d.attrs[i].name);
      merge_register(e->attrs, d, d.attrs[i]);
    }
    if (e->exists.empty() && e->attrs.empty()) erase_edge_record(e);
    gc_candidates.push_back(op.key.from);
    gc_candidates.push_back(op.key.to);
  }
}

void Graph::Impl::kill_removed_ids(const GraphDelta& d) {
  // A removed dot that is a node's id removes that node, whatever key the fragment lists it
  // under: an honest delta lists it as the node's own removal, and a forged one must not delete
  // the node while leaving its data behind (a zombie).
  for (const Dot& x : d.removed)
    if (find_node(NodeId{x}) != nullptr) {
      pending_kills.push_back(NodeId{x});
      gc_candidates.push_back(NodeId{x});
    }
}

void Graph::Impl::after_merge(const GraphDelta& d, bool full_gc) {
  kill_removed_ids(d);
  for (NodeId id : pending_kills) {
    NodeRec* r = find_node(id);
    if (r && r->alive) {
      touch_node(r);
      touch_incident_edges(r);
      set_alive(r, false, {}, {});
      gc_candidates.push_back(id);
    }
  }
  pending_kills.clear();
  ctx.join(d.context);
  d.for_each_mentioned_dot([&](const Dot& x) { ctx.add(x); });
  if (!full_gc) {
    // Data held for a node whose creation has not arrived (a placeholder) is dropped once the
    // node's id is in the context: the node is then deleted, and nothing may touch it again. An
    // honest delta's context covers only dots it mints (and counters skipped unused), so only a
    // forged one covers such an id; the check costs a lookup per context dot, or a scan of the
    // node table for a context that skips many counters.
    std::uint64_t span = 0;
    d.context.for_each_range([&](const ReplicaId&, std::uint64_t lo, std::uint64_t hi) { span += hi - lo + 1; });
    auto placeholder = [&](NodeId id) {
      const NodeRec* r = find_node(id);
      if (r != nullptr && !r->alive) gc_candidates.push_back(id);
    };
    if (span <= 256)
      d.context.for_each_range([&](const ReplicaId& rep, std::uint64_t lo, std::uint64_t hi) {
        for (std::uint64_t c = lo; c <= hi; ++c) placeholder(NodeId{Dot{rep, c}});
      });
    else
      for (const auto& [id, r] : nodes)
        if (!r.alive && d.context.contains(id.dot)) gc_candidates.push_back(id);
  }
  if (full_gc) {
    for (const auto& [id, r] : nodes)
      if (!r.alive) gc_candidates.push_back(id);
  }
  gc_candidates_sweep();
  if (rt_dirty) recompute_rt(nullptr);
  finish_tracking(false, d.origin, nullptr);
}

void Graph::Impl::merge_delta(const GraphDelta& d) {
  ++epoch;
  begin_tracking();
  if (tracker.enabled) {
    // Nodes and edges the delta may delete (a node by its own removal, or by any removed dot that
    // is its id: after_merge()): their deletion events carry what they held before the delta.
    for (const GraphDelta::NodeOp& op : d.nodes)
      if (op.removed)
        if (NodeRec* r = find_node(op.id)) save_last(r);
    for (const Dot& x : d.removed)
      if (NodeRec* r = find_node(NodeId{x})) save_last(r);
    // An edge written and then deleted in one transaction comes as two operations.
    for (const GraphDelta::EdgeOp& op : d.edges)
      if (!op.removed.empty())
        if (EdgeRec* e = find_edge(op.key)) save_last(*e);
  }
  merge_ops(d);
  after_merge(d, false);
}

void add_held(const GraphDelta& s, std::unordered_set<Dot>& held) {
  held.reserve(held.size() + s.values.size() + s.added.size() + s.claims.size() + s.nodes.size() + s.keep.size());
  for (const auto& n : s.nodes)
    if (n.has_header) held.insert(n.id.dot);
  for (const auto& e : s.values) held.insert(e.dot);
  for (const auto& x : s.added) held.insert(x);
  for (const auto& e : s.claims) held.insert(e.dot);
  for (const auto& x : s.keep) held.insert(x);
}

void Graph::Impl::merge_state(const GraphDelta& s) {
  ++epoch;
  begin_tracking();
  // Dots of the entries the sender holds; only our own records are checked against them, so a
  // replica that holds nothing yet (a joiner, a reload from a store) skips building the set.
  if (!nodes.empty() || !edges.empty()) {
    std::unordered_set<Dot> held;
    add_held(s, held);
    remove_unheld(s.context, held);
  }
  merge_ops(s);
  after_merge(s, true);
}

void Graph::Impl::remove_unheld(const crdt::CausalContext& context, const std::unordered_set<Dot>& held) {
  auto removed_there = [&](const Dot& x) { return context.contains(x) && held.count(x) == 0; };

  for (auto& [id, r] : nodes) {
    bool touched = false;
    if (r.alive && removed_there(id.dot)) {
      save_last(&r);
      pending_kills.push_back(id);
      touched = true;
    }
    for (AttrSlot& slot : r.attrs) {
      bool any = false;
      for (const auto& e : slot.reg) any = any || removed_there(e.dot);
      if (!any) continue;
      touch_attr(&r, slot.name);
      slot.reg.erase_if([&](const crdt::Entry<Value>& e) { return removed_there(e.dot); });
      touched = true;
    }
    r.attrs.erase(std::remove_if(r.attrs.begin(), r.attrs.end(), [](const AttrSlot& a) { return a.reg.empty(); }),
                  r.attrs.end());
    std::size_t gone = r.claim.erase_if([&](const crdt::Entry<RtClaim>& e) {
      if (!removed_there(e.dot)) return false;
      index_claim_entry(e.value, -1);
      return true;
    });
    if (gone > 0) {
      sync_claimant(&r);
      rt_dirty = true;
      touched = true;
    }
    if (touched) gc_candidates.push_back(id);
  }
  std::vector<EdgeRec*> emptied;
  for (auto& [key, e] : edges) {
    bool hit = false;
    for (const Dot& x : e.exists) hit = hit || removed_there(x);
    for (const AttrSlot& slot : e.attrs)
      for (const auto& en : slot.reg) hit = hit || removed_there(en.dot);
    if (!hit) continue;
    save_last(e);
    touch_edge(e);
    touch_edge_version(e);
    crdt::DotSet kept;
    for (const Dot& x : e.exists)
      if (!removed_there(x)) kept.insert(x);
    e.exists = kept;
    for (AttrSlot& slot : e.attrs) {
      touch_edge_attr(e, slot.name);
      slot.reg.erase_if([&](const crdt::Entry<Value>& en) { return removed_there(en.dot); });
    }
    e.attrs.erase(std::remove_if(e.attrs.begin(), e.attrs.end(), [](const AttrSlot& a) { return a.reg.empty(); }),
                  e.attrs.end());
    if (e.exists.empty() && e.attrs.empty()) emptied.push_back(&e);
  }
  for (EdgeRec* e : emptied) {
    gc_candidates.push_back(e->key.from);
    gc_candidates.push_back(e->key.to);
    erase_edge_record(e);
  }
}

}  // namespace quiver::graph
