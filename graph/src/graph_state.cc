// State transfer, digest, invariants.

#include <algorithm>

#include "codec_format.h"
#include "graph_impl.h"

namespace quiver::graph {
namespace {

void hash_node_id(Hasher& h, NodeId id) {
  h.u64(id.dot.replica.agent).u64(id.dot.replica.incarnation).u64(id.dot.counter);
}
void hash_dot(Hasher& h, const Dot& d) { h.u64(d.replica.agent).u64(d.replica.incarnation).u64(d.counter); }
void hash_pose(Hasher& h, const Pose& p) {
  for (double x : p.translation) h.f64(x);
  for (double x : p.rotation) h.f64(x);
}
void hash_edge_key(Hasher& h, const EdgeKey& k) {
  hash_node_id(h, k.from);
  hash_node_id(h, k.to);
  h.str(k.type.str());
}
using internal::u32;

/// Sum of the digests of every register entry in an attribute list; `owner` hashes the node id
/// or edge key the list belongs to, `tag` tells nodes from edges.
template <class HashOwner>
Digest128 digest_attrs(const AttrList& attrs, std::uint64_t tag, HashOwner&& owner) {
  Digest128 sum;
  for (const AttrSlot& slot : attrs)
    for (const auto& e : slot.reg) {
      Hasher h(tag);
      owner(h);
      h.str(slot.name.str());
      hash_dot(h, e.dot);
      h.u64(e.fence);
      e.value.hash_into(h);
      sum += h.digest();
    }
  return sum;
}

}  // namespace

GraphDelta Graph::state() const { return state_diff(crdt::CausalContext{}); }

namespace {

void emit_attrs(const AttrList& attrs, const crdt::CausalContext& theirs, GraphDelta& out) {
  for (const AttrSlot& slot : attrs) {
    GraphDelta::AttrOp a;
    a.name = slot.name;
    a.removed = {u32(out.removed.size()), u32(out.removed.size())};
    a.added.begin = u32(out.values.size());
    for (const auto& e : slot.reg) {
      if (theirs.contains(e.dot)) out.keep.push_back(e.dot);
      else out.values.push_back(e);
    }
    a.added.end = u32(out.values.size());
    if (!a.added.empty()) out.attrs.push_back(a);
  }
}

}  // namespace

void emit_node(NodeId id, const NodeRec& r, const crdt::CausalContext& theirs, GraphDelta& out) {
  GraphDelta::NodeOp op;
  op.id = id;
  op.type = r.type;  // stated even without the header (docs/security.md)
  if (r.alive) {
    if (theirs.contains(id.dot)) {
      out.keep.push_back(id.dot);
    } else {
      op.has_header = true;
      op.type = r.type;
      op.name = r.name;
    }
  }
  op.attrs.begin = u32(out.attrs.size());
  emit_attrs(r.attrs, theirs, out);
  op.attrs.end = u32(out.attrs.size());
  op.claim_removed = {u32(out.removed.size()), u32(out.removed.size())};
  op.claim_added.begin = u32(out.claims.size());
  for (const auto& e : r.claim) {
    if (theirs.contains(e.dot)) out.keep.push_back(e.dot);
    else out.claims.push_back(e);
  }
  op.claim_added.end = u32(out.claims.size());
  op.samples.begin = u32(out.samples.size());
  for (const RtSample& s : r.history)
    if (!theirs.contains(s.dot)) out.samples.push_back(s);
  op.samples.end = u32(out.samples.size());
  if (op.has_header || !op.attrs.empty() || !op.claim_added.empty() || !op.samples.empty())
    out.nodes.push_back(std::move(op));
}

void emit_edge(const EdgeKey& key, const EdgeRec& e, const crdt::CausalContext& theirs, GraphDelta& out) {
  GraphDelta::EdgeOp op;
  op.key = key;
  op.removed = {u32(out.removed.size()), u32(out.removed.size())};
  op.added.begin = u32(out.added.size());
  for (const Dot& x : e.exists) {
    if (theirs.contains(x)) out.keep.push_back(x);
    else out.added.push_back(x);
  }
  op.added.end = u32(out.added.size());
  op.attrs.begin = u32(out.attrs.size());
  emit_attrs(e.attrs, theirs, out);
  op.attrs.end = u32(out.attrs.size());
  if (!op.added.empty() || !op.attrs.empty()) out.edges.push_back(op);
}

GraphDelta Graph::state_diff(const crdt::CausalContext& theirs) const {
  const Impl& g = *impl_;
  GraphDelta out;
  out.kind = GraphDelta::Kind::kState;
  out.origin = g.self;
  out.context = g.ctx;
  // Every array sized at once (an upper bound: entries the receiver holds go to `keep`), not by
  // doubling: a 10k-node state is megabytes, and memory touched for the first time is what
  // building it costs.
  std::size_t n_attrs = 0, n_values = 0, n_claims = 0, n_samples = 0, n_added = 0;
  auto count_attrs = [&](const AttrList& attrs) {
    n_attrs += attrs.size();
    for (const AttrSlot& slot : attrs) n_values += slot.reg.size();
  };
  for (const auto& [id, r] : g.nodes) {
    count_attrs(r.attrs);
    n_claims += r.claim.size();
    n_samples += r.history.size();
  }
  for (const auto& [key, e] : g.edges) {
    count_attrs(e.attrs);
    n_added += e.exists.size();
  }
  out.nodes.reserve(g.nodes.size());
  out.edges.reserve(g.edges.size());
  out.attrs.reserve(n_attrs);
  out.values.reserve(n_values);
  out.claims.reserve(n_claims);
  out.samples.reserve(n_samples);
  out.added.reserve(n_added);
  for (const auto& [id, r] : g.nodes) emit_node(id, r, theirs, out);
  for (const auto& [key, e] : g.edges) emit_edge(key, e, theirs, out);
  return out;
}

Digest128 Graph::digest() const {
  const Impl& g = *impl_;
  Digest128 total = g.ctx.digest();
  for (const auto& [id, r] : g.nodes) {
    if (r.alive) {
      Hasher h(1);
      hash_node_id(h, id);
      h.str(r.type.str()).str(r.name);
      total += h.digest();
    }
    total += digest_attrs(r.attrs, 2, [&id = id](Hasher& h) { hash_node_id(h, id); });
    for (const auto& e : r.claim) {
      Hasher h(3);
      hash_node_id(h, id);
      hash_dot(h, e.dot);
      hash_node_id(h, e.value.parent);
      hash_pose(h, e.value.pose);
      h.i64(e.value.stamp);
      hash_node_id(h, e.value.fallback_parent);
      hash_pose(h, e.value.fallback_pose);
      h.i64(e.value.fallback_stamp);
      hash_dot(h, e.value.fallback_epoch);
      total += h.digest();
    }
    for (const RtSample& s : r.history) {
      Hasher h(4);
      hash_node_id(h, id);
      h.i64(s.stamp);
      hash_dot(h, s.dot);
      hash_dot(h, s.epoch);
      hash_pose(h, s.pose);
      total += h.digest();
    }
  }
  for (const auto& [key, e] : g.edges) {
    for (const Dot& x : e.exists) {
      Hasher h(5);
      hash_edge_key(h, key);
      hash_dot(h, x);
      total += h.digest();
    }
    total += digest_attrs(e.attrs, 6, [&key = key](Hasher& h) { hash_edge_key(h, key); });
  }
  return total;
}

std::vector<std::string> Graph::check_invariants() const {
  const Impl& g = *impl_;
  std::vector<std::string> v;
  auto dot_in_ctx = [&](const Dot& d, const std::string& where) {
    if (!g.ctx.contains(d)) v.push_back("dot " + d.to_string() + " of " + where + " is not in the causal context");
  };
  std::size_t alive = 0;
  for (const auto& [id, r] : g.nodes) {
    std::string nname = "node " + id.to_string();
    if (!(r.id == id)) v.push_back(nname + ": record id mismatch");
    if (r.alive) {
      ++alive;
      dot_in_ctx(id.dot, nname);
      auto it = g.by_name.find(r.name);
      if (it == g.by_name.end() || std::find(it->second.begin(), it->second.end(), &r) == it->second.end())
        v.push_back(nname + ": missing from the name index");
    } else {
      if (g.ctx.contains(id.dot)) v.push_back(nname + ": deleted node still holds data");
      if (r.rt_parent || !r.rt_children.empty()) v.push_back(nname + ": invisible node in the RT tree");
      if (r.is_empty_placeholder()) v.push_back(nname + ": empty placeholder record kept");
    }
    for (const AttrSlot& s : r.attrs) {
      if (s.reg.empty()) v.push_back(nname + ": empty attribute slot " + s.name.str());
      for (const auto& e : s.reg) dot_in_ctx(e.dot, nname + " attribute " + s.name.str());
    }
    for (const auto& e : r.claim) dot_in_ctx(e.dot, nname + " RT claim");
    for (const RtSample& s : r.history) dot_in_ctx(s.dot, nname + " RT sample");
    if (r.history.size() > kRtHistoryDepth) v.push_back(nname + ": RT history over its depth");
    if (!std::is_sorted(r.history.begin(), r.history.end(), sample_less)) v.push_back(nname + ": RT history unsorted");
    for (const EdgeRec* e : r.out)
      if (!(e->key.from == id)) v.push_back(nname + ": adjacency lists a foreign edge");
    for (const EdgeRec* e : r.in)
      if (!(e->key.to == id)) v.push_back(nname + ": adjacency lists a foreign edge");
    // RT tree: at most one parent (structural), parent visible, and no cycle.
    if (r.rt_parent) {
      if (!r.rt_parent->alive) v.push_back(nname + ": RT parent is not visible");
      const auto& sib = r.rt_parent->rt_children;
      if (std::find(sib.begin(), sib.end(), &r) == sib.end()) v.push_back(nname + ": RT parent does not list it");
      std::size_t steps = 0;
      for (const NodeRec* x = r.rt_parent; x; x = x->rt_parent)
        if (++steps > g.nodes.size() || x == &r) {
          v.push_back(nname + ": RT cycle");
          break;
        }
    }
    for (const NodeRec* c : r.rt_children)
      if (c->rt_parent != &r) v.push_back(nname + ": RT child does not point back");
  }
  if (alive != g.alive_count) v.push_back("alive node count is out of date");
  for (const auto& [key, e] : g.edges) {
    std::string ename = "edge " + key.to_string();
    if (e.exists.empty() && e.attrs.empty()) v.push_back(ename + ": empty edge record kept");
    for (const Dot& x : e.exists) dot_in_ctx(x, ename);
    for (const AttrSlot& s : e.attrs)
      for (const auto& en : s.reg) dot_in_ctx(en.dot, ename + " attribute " + s.name.str());
    const NodeRec* f = g.find_node(key.from);
    const NodeRec* t = g.find_node(key.to);
    if (!f || std::find(f->out.begin(), f->out.end(), &e) == f->out.end() || !t ||
        std::find(t->in.begin(), t->in.end(), &e) == t->in.end())
      v.push_back(ename + ": missing from adjacency");
  }
  // The public view: no visible edge with an invisible endpoint.
  for (NodeId n : nodes()) {
    for (const EdgeKey& k : edges_from(n))
      if (!has_node(k.to)) v.push_back("visible edge " + k.to_string() + " dangles");
    for (const EdgeKey& k : edges_to(n))
      if (!has_node(k.from)) v.push_back("visible edge " + k.to_string() + " dangles");
  }
  return v;
}

Graph::Stats Graph::stats() const {
  const Impl& g = *impl_;
  Stats s;
  s.node_records = g.nodes.size();
  s.edge_records = g.edges.size();
  for (const auto& [id, r] : g.nodes) {
    s.entries += (r.alive ? 1 : 0) + r.claim.size();
    for (const AttrSlot& a : r.attrs) s.entries += a.reg.size();
    s.samples += r.history.size();
  }
  for (const auto& [k, e] : g.edges) {
    s.entries += e.exists.size();
    for (const AttrSlot& a : e.attrs) s.entries += a.reg.size();
  }
  s.context_ranges = g.ctx.range_count();
  return s;
}

}  // namespace quiver::graph
