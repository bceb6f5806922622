// Local changes recorded: dot minting, and each local change applied to the records and written
// into the outgoing delta.

#include <algorithm>
#include <unordered_map>
#include <unordered_set>

#include "quiver/graph/limits.h"

#include "codec_format.h"
#include "graph_impl.h"

namespace quiver::graph {
namespace {
// In a namespace of their own: these names must not meet the codec's flags (kClaim, ...) in a
// unity build, where they would be found first.
namespace Section {
enum Kind { kHeader, kAttrs, kClaim, kSamples, kRemoved };
}

GraphDelta::Span open_span(std::size_t at) {
  return GraphDelta::Span{static_cast<std::uint32_t>(at), static_cast<std::uint32_t>(at)};
}
using internal::u32;
}  // namespace

// ---------------------------------------------------------------- recording

Dot Graph::Impl::mint() {
  next_counter = std::max(next_counter, std::min(ctx.max_counter_overall(), crdt::kClockCeiling)) + 1;
  return Dot{self, next_counter};
}

bool Graph::Impl::can_mint(std::uint64_t n) const {
  const std::uint64_t base = std::max(next_counter, std::min(ctx.max_counter_overall(), crdt::kClockCeiling));
  return n <= crdt::kMaxCounter - base;
}

void Graph::Impl::unreserve(const std::vector<std::uint64_t>& mine) {
  if (mine.empty()) return;
  if (mine.size() == reserved.size()) {  // the only open transaction that reserved any
    reserved.clear();
    return;
  }
  auto m = mine.begin();
  reserved.erase(std::remove_if(reserved.begin(), reserved.end(),
                                [&](std::uint64_t c) {
                                  while (m != mine.end() && *m < c) ++m;
                                  return m != mine.end() && *m == c;
                                }),
                 reserved.end());
}

void Graph::Impl::publish_own_dots(CommitInfo& info) {
  const std::uint64_t lo = ctx.contiguous(self) + 1, hi = next_counter;
  if (lo > hi) return;
  auto publish = [&](std::uint64_t a, std::uint64_t b) {
    ctx.add_range(self, a, b);
    out.context.add_range(self, a, b);
    if (info.first_counter == 0 || a < info.first_counter) info.first_counter = a;
    info.last_counter = std::max(info.last_counter, b);
  };
  if (reserved.empty() && ctx.max_counter(self) < lo) {  // the usual case: one range
    publish(lo, hi);
    return;
  }
  // Segments between counters other open transactions hold, minus what earlier commits published.
  crdt::CausalContext todo;
  std::uint64_t a = lo;
  for (auto it = std::lower_bound(reserved.begin(), reserved.end(), lo); a <= hi; ++it) {
    const bool last = it == reserved.end() || *it > hi;
    const std::uint64_t b = last ? hi : *it - 1;
    if (a <= b) todo.add_range(self, a, b);
    if (last) break;
    a = *it + 1;
  }
  todo.minus(ctx).for_each_range([&](const ReplicaId&, std::uint64_t x, std::uint64_t y) { publish(x, y); });
}

GraphDelta::NodeOp& Graph::Impl::out_node(NodeId id, int section) {
  if (!out.nodes.empty() && out.nodes.back().id == id) {
    auto& last = out.nodes.back();
    bool fits = false;
    switch (section) {
      case Section::kHeader: fits = !last.has_header; break;
      case Section::kAttrs:
        fits = last.attrs.end == out.attrs.size();
        break;
      case Section::kClaim: fits = last.claim_added.empty() && last.claim_removed.empty(); break;
      case Section::kSamples: fits = last.samples.end == out.samples.size(); break;
      case Section::kRemoved: fits = true; break;
    }
    if (fits) {
      if (section == Section::kAttrs && last.attrs.empty()) last.attrs = open_span(out.attrs.size());
      if (section == Section::kSamples && last.samples.empty()) last.samples = open_span(out.samples.size());
      return last;
    }
  }
  GraphDelta::NodeOp op;
  op.id = id;
  // Every op states its node's type, so that a receiver can check the change against a policy
  // from the delta alone (docs/security.md), whatever it already holds.
  if (const NodeRec* r = find_node(id)) op.type = r->type;
  op.attrs = open_span(out.attrs.size());
  op.claim_removed = open_span(out.removed.size());
  op.claim_added = open_span(out.claims.size());
  op.samples = open_span(out.samples.size());
  out.nodes.push_back(std::move(op));
  return out.nodes.back();
}

GraphDelta::EdgeOp& Graph::Impl::out_edge(const EdgeKey& key) {
  if (!out.edges.empty() && out.edges.back().key == key && out.edges.back().attrs.end == out.attrs.size())
    return out.edges.back();
  GraphDelta::EdgeOp op;
  op.key = key;
  op.removed = open_span(out.removed.size());
  op.added = open_span(out.added.size());
  op.attrs = open_span(out.attrs.size());
  out.edges.push_back(op);
  return out.edges.back();
}

namespace {
// Appends an AttrOp that removes every dot of `slot` and (if v) adds (d, *v, fence). Updates the
// slot.
GraphDelta::AttrOp record_write(GraphDelta& out, AttrSlot& slot, const Dot* d, const Value* v,
                                std::uint64_t fence = 0) {
  GraphDelta::AttrOp a;
  a.name = slot.name;
  a.removed = open_span(out.removed.size());
  for (const auto& e : slot.reg) out.removed.push_back(e.dot);
  a.removed.end = u32(out.removed.size());
  slot.reg.clear();
  a.added = open_span(out.values.size());
  if (v) {
    slot.reg.insert(*d, *v, fence);
    out.values.push_back(crdt::Entry<Value>{*d, *v, fence});
  }
  a.added.end = u32(out.values.size());
  return a;
}
}  // namespace

void Graph::Impl::local_write_attr(NodeRec* r, Symbol name, Value v) {
  Dot d = mint();
  touch_attr(r, name);
  AttrSlot* slot = find_slot(r->attrs, name);
  if (slot == nullptr) {
    r->attrs.push_back(AttrSlot{name, {}});
    slot = &r->attrs.back();
  }
  auto& op = out_node(r->id, Section::kAttrs);
  out.attrs.push_back(record_write(out, *slot, &d, &v, fence(r->id)));
  op.attrs.end = u32(out.attrs.size());
}

void Graph::Impl::local_remove_attr(NodeRec* r, Symbol name) {
  AttrSlot* slot = find_slot(r->attrs, name);
  if (slot == nullptr) return;
  touch_attr(r, name);
  auto& op = out_node(r->id, Section::kAttrs);
  out.attrs.push_back(record_write(out, *slot, nullptr, nullptr));
  op.attrs.end = u32(out.attrs.size());
  r->attrs.erase(r->attrs.begin() + (slot - r->attrs.data()));
}

void Graph::Impl::local_create_node(NodeId id, Symbol type, const std::string& name,
                                    const std::vector<std::pair<Symbol, Value>>& attrs) {
  NodeRec& r = node_record(id);
  touch_node(&r);
  touch_incident_edges(&r);
  set_alive(&r, true, type, name);
  auto& op = out_node(id, Section::kHeader);
  op.has_header = true;
  op.type = type;
  op.name = name;
  for (const auto& [k, v] : attrs) local_write_attr(&r, k, v);
}

void Graph::Impl::record_attr_removals(std::vector<GraphDelta::AttrOp>& ops, AttrList& attrs) {
  for (AttrSlot& s : attrs) ops.push_back(record_write(out, s, nullptr, nullptr));
}

void Graph::Impl::local_delete_node(NodeRec* r) {
  NodeId id = r->id;
  save_last(r);
  touch_node(r);
  touch_incident_edges(r);
  {
    auto& op = out_node(id, Section::kRemoved);
    op.removed = true;
  }
  if (!r->attrs.empty()) {
    auto& op = out_node(id, Section::kAttrs);
    record_attr_removals(out.attrs, r->attrs);
    op.attrs.end = u32(out.attrs.size());
  }
  if (!r->claim.empty()) {
    auto& op = out_node(id, Section::kClaim);
    op.claim_removed = open_span(out.removed.size());
    for (const auto& e : r->claim) out.removed.push_back(e.dot);
    op.claim_removed.end = u32(out.removed.size());
  }
  for (EdgeRec* e : r->incident()) {
    if (e->exists.empty() && e->attrs.empty()) continue;
    record_edge_removal(*e);
  }
  // RT edges to the children: remove the claims that name this node as parent.
  std::vector<NodeRec*> children = r->rt_children;
  for (NodeRec* c : children) {
    auto& op = out_node(c->id, Section::kClaim);
    op.claim_removed = open_span(out.removed.size());
    c->claim.erase_if([&](const crdt::Entry<RtClaim>& e) {
      if (e.value.parent != id) return false;
      out.removed.push_back(e.dot);
      index_claim_entry(e.value, -1);
      return true;
    });
    op.claim_removed.end = u32(out.removed.size());
    claim_updated(c);
  }
  kill_record(r);
}

void Graph::Impl::local_insert_edge(const EdgeKey& key, const std::vector<std::pair<Symbol, Value>>& attrs) {
  EdgeRec& e = edge_record(key);
  touch_edge_version(e);
  Dot d = mint();
  GraphDelta::EdgeOp op;
  op.key = key;
  op.removed = open_span(out.removed.size());
  for (const Dot& x : e.exists) out.removed.push_back(x);
  op.removed.end = u32(out.removed.size());
  op.added = open_span(out.added.size());
  out.added.push_back(d);
  op.added.end = u32(out.added.size());
  e.exists = crdt::DotSet();
  e.exists.insert(d);
  // A re-insert replaces the attributes: old values do not come back to life.
  op.attrs = open_span(out.attrs.size());
  for (AttrSlot& s : e.attrs) {
    bool rewritten = false;
    for (const auto& kv : attrs) rewritten = rewritten || kv.first == s.name;
    if (!rewritten) {
      touch_edge_attr(e, s.name);
      out.attrs.push_back(record_write(out, s, nullptr, nullptr));
    }
  }
  e.attrs.erase(std::remove_if(e.attrs.begin(), e.attrs.end(), [](const AttrSlot& s) { return s.reg.empty(); }),
                e.attrs.end());
  const std::uint64_t attr_fence = attrs.empty() ? 0 : edge_fence(key);
  for (const auto& [name, v] : attrs) {
    AttrSlot* slot = find_slot(e.attrs, name);
    if (slot == nullptr) {
      e.attrs.push_back(AttrSlot{name, {}});
      slot = &e.attrs.back();
    }
    Dot ad = mint();
    touch_edge_attr(e, name);
    out.attrs.push_back(record_write(out, *slot, &ad, &v, attr_fence));
  }
  op.attrs.end = u32(out.attrs.size());
  out.edges.push_back(op);
}

void Graph::Impl::record_edge_removal(EdgeRec& e) {
  // The edge's existence dots and every attribute value, removed; nothing added.
  GraphDelta::EdgeOp op;
  op.key = e.key;
  op.removed = open_span(out.removed.size());
  for (const Dot& x : e.exists) out.removed.push_back(x);
  op.removed.end = u32(out.removed.size());
  op.added = open_span(out.added.size());
  op.attrs = open_span(out.attrs.size());
  record_attr_removals(out.attrs, e.attrs);
  op.attrs.end = u32(out.attrs.size());
  out.edges.push_back(op);
}

void Graph::Impl::local_delete_edge(EdgeRec* e) {
  save_last(*e);
  touch_edge(*e);
  // A re-insert in the same transaction turns this into an update: its removed attributes count.
  for (const AttrSlot& a : e->attrs) touch_edge_attr(*e, a.name);
  record_edge_removal(*e);
  erase_edge_record(e);
}

void Graph::Impl::local_write_edge_attr(EdgeRec* e, Symbol name, const Value* v) {
  AttrSlot* slot = find_slot(e->attrs, name);
  if (slot == nullptr) {
    if (v == nullptr) return;
    e->attrs.push_back(AttrSlot{name, {}});
    slot = &e->attrs.back();
  }
  touch_edge_attr(*e, name);
  Dot d = v ? mint() : Dot{};
  auto& op = out_edge(e->key);
  out.attrs.push_back(record_write(out, *slot, &d, v, v ? edge_fence(e->key) : 0));
  op.attrs.end = u32(out.attrs.size());
  if (v == nullptr) e->attrs.erase(e->attrs.begin() + (slot - e->attrs.data()));
}

void Graph::Impl::local_set_rt(NodeRec* parent, NodeRec* child, const Pose& pose, std::int64_t stamp) {
  if (rt_dirty) recompute_rt(nullptr);
  if (child->rt_parent == parent) {
    // A sample older than every kept one is dropped: nobody would keep it.
    record_sample(child, RtSample{stamp, mint(), child->rt_epoch, pose});
    return;
  }
  RtClaim c;
  c.parent = parent ? parent->id : NodeId{};
  c.pose = pose;
  c.stamp = stamp;
  if (child->rt_parent) {
    RtEdge cur = current_rt(*child);
    c.fallback_parent = cur.parent;
    c.fallback_pose = cur.pose;
    c.fallback_stamp = cur.stamp;
    c.fallback_epoch = cur.epoch;
  }
  Dot d = mint();
  auto& op = out_node(child->id, Section::kClaim);
  op.claim_removed = open_span(out.removed.size());
  for (const auto& e : child->claim) {
    out.removed.push_back(e.dot);
    index_claim_entry(e.value, -1);
  }
  op.claim_removed.end = u32(out.removed.size());
  child->claim.clear();
  child->claim.insert(d, c);
  index_claim_entry(c, +1);
  op.claim_added = open_span(out.claims.size());
  out.claims.push_back(crdt::Entry<RtClaim>{d, c});
  op.claim_added.end = u32(out.claims.size());
  claim_updated(child);
  // The move's own pose is the first sample of its epoch, so history covers it too.
  if (parent) record_sample(child, RtSample{stamp, mint(), d, pose});
}

bool Graph::Impl::record_sample(NodeRec* child, const RtSample& s) {
  if (!insert_sample(child, s)) return false;
  auto& op = out_node(child->id, Section::kSamples);
  out.samples.push_back(s);
  op.samples.end = u32(out.samples.size());
  return true;
}

void Graph::Impl::local_remove_rt(NodeRec* child) {
  if (rt_dirty) recompute_rt(nullptr);
  if (child->rt_parent == nullptr) return;
  local_set_rt(nullptr, child, Pose{}, 0);
}

}  // namespace quiver::graph
