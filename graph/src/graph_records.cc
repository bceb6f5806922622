// Graph's records and indexes: node and edge records, names, liveness, RT claims and samples,
// and the removal of records nothing refers to any more.

#include <algorithm>

#include "graph_impl.h"
#include "quiver/graph/limits.h"

namespace quiver::graph {

const char* to_string(ChangeKind k) {
  switch (k) {
    case ChangeKind::kCreated:
      return "created";
    case ChangeKind::kUpdated:
      return "updated";
    case ChangeKind::kDeleted:
      return "deleted";
  }
  return "unknown";
}

std::string EdgeKey::to_string() const {
  return from.to_string() + " -[" + type.str() + "]-> " + to.to_string();
}

bool canonical_less(const EdgeKey& a, const EdgeKey& b) {
  if (a.from != b.from) return a.from < b.from;
  if (a.to != b.to) return a.to < b.to;
  return text_less(a.type, b.type);
}

AttrSlot* find_slot(AttrList& attrs, Symbol name) {
  for (AttrSlot& s : attrs)
    if (s.name == name) return &s;
  return nullptr;
}
const AttrSlot* find_slot(const AttrList& attrs, Symbol name) {
  for (const AttrSlot& s : attrs)
    if (s.name == name) return &s;
  return nullptr;
}

namespace {
template <class T>
void swap_remove(std::vector<T>& v, const T& x) {
  auto it = std::find(v.begin(), v.end(), x);
  if (it != v.end()) {
    *it = v.back();
    v.pop_back();
  }
}
}  // namespace

// ---------------------------------------------------------------- records and indexes

bool Graph::Impl::edge_visible(const EdgeRec& e) const {
  if (e.exists.empty()) return false;
  const NodeRec* f = find_node(e.key.from);
  const NodeRec* t = find_node(e.key.to);
  return f && f->alive && t && t->alive;
}

NodeRec& Graph::Impl::node_record(NodeId id) {
  auto [it, fresh] = nodes.try_emplace(id);
  if (fresh) it->second.id = id;
  return it->second;
}

EdgeRec& Graph::Impl::edge_record(const EdgeKey& k) {
  auto [it, fresh] = edges.try_emplace(k);
  if (fresh) {
    it->second.key = k;
    node_record(k.from).out.push_back(&it->second);
    node_record(k.to).in.push_back(&it->second);
  }
  return it->second;
}

void Graph::Impl::erase_edge_record(EdgeRec* e) {
  EdgeKey k = e->key;
  NodeRec* f = find_node(k.from);
  NodeRec* t = find_node(k.to);
  if (f) swap_remove(f->out, e);
  if (t) swap_remove(t->in, e);
  edges.erase(k);
  if (f) erase_node_record_if_empty(f);
  if (t && t != f) erase_node_record_if_empty(t);
}

std::vector<EdgeRec*> NodeRec::incident() const {
  std::vector<EdgeRec*> v = out;
  for (EdgeRec* e : in)
    if (!(e->key.from == e->key.to)) v.push_back(e);
  return v;
}

void Graph::Impl::erase_node_record_if_empty(NodeRec* r) {
  if (r->is_empty_placeholder() && r->rt_children.empty()) nodes.erase(r->id);
}

const NodeRec* name_winner(const crdt::SmallVec<NodeRec*, 1>& v) {
  const NodeRec* best = nullptr;
  for (const NodeRec* r : v)
    if (best == nullptr || crdt::lamport_less(r->id.dot, best->id.dot)) best = r;
  return best;
}

void Graph::Impl::set_alive(NodeRec* r, bool alive, Symbol type, const std::string& name) {
  if (r->alive == alive) return;
  touch_rt(r);  // its RT edges appear or go with it
  for (const NodeRec* c : r->rt_children) touch_rt(c);
  if (alive) {
    r->alive = true;
    r->type = type;
    r->name = name;
    ++alive_count;
    auto& sakes = by_name[r->name];
    // An earlier namesake takes the name from the node that held it: that one is renamed.
    const NodeRec* holder = sakes.empty() ? nullptr : name_winner(sakes);
    sakes.push_back(r);
    if (holder && name_winner(sakes) == r)
      touch_renamed(const_cast<NodeRec*>(holder), holder->name);
    by_type[r->type].insert(r);
  } else {
    r->alive = false;
    --alive_count;
    auto it = by_name.find(r->name);
    if (it != by_name.end()) {
      const bool held = name_winner(it->second) == r;
      for (NodeRec** p = it->second.begin(); p != it->second.end(); ++p)
        if (*p == r) {
          it->second.swap_erase(p);
          break;
        }
      if (it->second.empty())
        by_name.erase(it);
      else if (held) {  // the name passes on to the earliest remaining namesake
        NodeRec* heir = const_cast<NodeRec*>(name_winner(it->second));
        touch_renamed(heir, heir->name + "~" + heir->id.to_string());
      }
    }
    auto tt = by_type.find(r->type);
    if (tt != by_type.end()) {
      tt->second.erase(r);
      if (tt->second.empty()) by_type.erase(tt);
    }
  }
  if (claimants.count(r) || claim_parent_refs.count(r->id)) rt_dirty = true;
}

void Graph::Impl::index_claim_entry(const RtClaim& c, int delta) {
  for (const NodeId* p : {&c.parent, &c.fallback_parent}) {
    if (p->is_null()) continue;
    int& n = claim_parent_refs[*p];
    n += delta;
    if (n <= 0) claim_parent_refs.erase(*p);
  }
}

bool Graph::Impl::insert_sample(NodeRec* r, const RtSample& s) {
  auto& h = r->history;
  auto pos = std::lower_bound(h.begin(), h.end(), s, sample_less);
  if (pos != h.end() && pos->dot == s.dot) return false;
  for (const RtSample& x : h)
    if (x.dot == s.dot) return false;
  touch_rt(r);
  if (h.size() >= kRtHistoryDepth) {
    if (pos == h.begin()) return false;  // older than everything kept
    h.erase(h.begin());
    pos = std::lower_bound(h.begin(), h.end(), s, sample_less);
  }
  h.insert(pos, s);
  return true;
}

void Graph::Impl::kill_record(NodeRec* r) {
  NodeId id = r->id;
  touch_node(r);
  touch_incident_edges(r);
  if (r->alive) set_alive(r, false, {}, {});
  // RT edges in which r takes part.
  touch_rt(r);
  for (NodeRec* c : r->rt_children) touch_rt(c);
  for (NodeRec* c : r->rt_children) c->rt_parent = nullptr;
  r->rt_children.clear();
  if (r->rt_parent) {
    swap_remove(r->rt_parent->rt_children, r);
    r->rt_parent = nullptr;
  }
  for (const auto& e : r->claim) index_claim_entry(e.value, -1);
  r->claim.clear();
  claimants.erase(r);
  r->history.clear();
  r->attrs.clear();
  if (claim_parent_refs.count(id)) rt_dirty = true;
  rt_dirty = true;
  for (EdgeRec* e : r->incident()) {
    // The other endpoint may be erased as an empty placeholder; r itself is kept until below.
    NodeId other = e->key.from == id ? e->key.to : e->key.from;
    NodeRec* o = other == id ? nullptr : find_node(other);
    if (o) swap_remove(e->key.from == id ? o->in : o->out, e);
    edges.erase(EdgeKey(e->key));
    if (o) erase_node_record_if_empty(o);
  }
  nodes.erase(id);
}

void Graph::Impl::gc_candidates_sweep() {
  for (NodeId id : gc_candidates) {
    NodeRec* r = find_node(id);
    if (r == nullptr) continue;
    if (!r->alive && ctx.contains(id.dot))
      kill_record(r);
    else
      erase_node_record_if_empty(r);
  }
  gc_candidates.clear();
}

}  // namespace quiver::graph
