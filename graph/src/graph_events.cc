// Graph's change events: what a commit or merge touches is tracked, then reported to the
// subscribers as one ChangeBatch of created, updated and deleted nodes and edges.

#include <algorithm>

#include "graph_impl.h"

namespace quiver::graph {

RtView Graph::Impl::rt_view(const NodeRec& r) const {
  RtView v;
  if (!r.alive || r.rt_parent == nullptr) return v;
  RtEdge e = current_rt(r);
  v.parent = e.parent;
  v.epoch = e.epoch;
  v.pose = e.pose;
  v.stamp = e.stamp;
  Hasher h(7);
  for (const RtSample& s : r.history)
    if (s.epoch == r.rt_epoch)
      h.i64(s.stamp).u64(s.dot.replica.agent).u64(s.dot.replica.incarnation).u64(s.dot.counter);
  v.history = h.h64();
  return v;
}

void Graph::Impl::touch_edge(const EdgeRec& e) {
  if (!tracker.enabled || tracker.edge_touched(e.key)) return;
  bool was = !e.exists.empty();
  if (was) {
    const NodeRec* f = find_node(e.key.from);
    const NodeRec* t = find_node(e.key.to);
    was = tracker.node_was_alive(e.key.from, f && f->alive) &&
          tracker.node_was_alive(e.key.to, t && t->alive);
  }
  tracker.touch_edge(e.key, was);
}

std::uint64_t register_fingerprint(const AttrList& attrs, Symbol name) {
  // What a reader sees: the winning value and the set of concurrent values, not the dots that
  // carry them, so that writing the value an attribute already has (a re-inserted edge's
  // unchanged attributes, a set() of the same value) is no change, as DSR reports it.
  const AttrSlot* s = find_slot(attrs, name);
  if (s == nullptr) return 0;
  auto value_hash = [](const Value& v) {
    Hasher h(0xa77);
    v.hash_into(h);
    return h.h64();
  };
  std::uint64_t fp = mix64(s->reg.size());
  for (const auto& e : s->reg) fp += mix64(value_hash(e.value));
  if (const auto* w = winner(s->reg)) fp ^= mix64(value_hash(w->value) + 1);
  return fp;
}

std::uint64_t dots_fingerprint(const crdt::DotSet& dots) {
  // What edge_version() shows: the greatest existence dot.
  Dot best;
  for (const Dot& d : dots)
    if (best.is_null() || crdt::lamport_less(best, d)) best = d;
  return best.is_null() ? 0 : mix64(hash_value(best));
}

void Graph::Impl::touch_edge_version(const EdgeRec& e) {
  if (!tracker.enabled) return;
  touch_edge(e);
  auto* t = tracker.touch_edge(e.key, false);
  if (!t->version_saved) {
    t->version_saved = true;
    t->version_before = dots_fingerprint(e.exists);
  }
}

void Graph::Impl::touch_renamed(NodeRec* r, std::string before) {
  if (!tracker.enabled) return;
  auto* t = tracker.touch_node(r->id, r->alive, r->type);
  if (!t->name_saved) {
    t->name_saved = true;
    t->name_before = std::move(before);
  }
}

std::string Graph::Impl::visible_name(const NodeRec& r) const {
  auto it = by_name.find(r.name);
  if (it == by_name.end() || it->second.size() == 1 || name_winner(it->second) == &r) return r.name;
  return r.name + "~" + r.id.to_string();
}

void Graph::Impl::touch_edge_attr(const EdgeRec& e, Symbol name) {
  if (!tracker.enabled) return;
  touch_edge(e);
  save_attr(tracker.touch_edge(e.key, false)->attrs, name, e.attrs);
}

namespace {

std::vector<std::pair<Symbol, Value>> winning_values(const AttrList& attrs) {
  std::vector<std::pair<Symbol, Value>> out;
  out.reserve(attrs.size());
  for (const AttrSlot& a : attrs)
    if (const auto* w = winner(a.reg)) out.emplace_back(a.name, w->value);
  return out;
}

}  // namespace

// What a deleted RT edge held: its pose ("translation", x y z; "rotation", the quaternion w x y z)
// and its attributes (kept on the child as rt:<name>), the child's last ones if it went too.
std::vector<std::pair<Symbol, Value>> Graph::Impl::last_rt_values(const RtView& before, const std::vector<NodeChange>& nodes,
                                                                  NodeId child, const NodeRec* now) const {
  static const Symbol translation("translation"), rotation("rotation");
  std::vector<std::pair<Symbol, Value>> out;
  out.emplace_back(translation, DoubleVec(before.pose.translation.begin(), before.pose.translation.end()));
  out.emplace_back(rotation, DoubleVec(before.pose.rotation.begin(), before.pose.rotation.end()));
  std::vector<std::pair<Symbol, Value>> attrs;
  for (const NodeChange& n : nodes)
    if (n.id == child && n.kind == ChangeKind::kDeleted) attrs = n.values;
  if (attrs.empty() && now != nullptr && now->alive) attrs = winning_values(now->attrs);
  for (auto& [name, value] : attrs)
    if (name.str().starts_with(kRtAttrPrefix)) out.emplace_back(Symbol(name.str().substr(kRtAttrPrefix.size())), value);
  return out;
}

// A change of an RT edge's attributes (rt:<name> on its child) is a change of that edge too, as
// DSR reports it: named <name> in the edge's change, merged with a pose change of the same edge.
void Graph::Impl::report_rt_attrs(Dispatch& d, std::size_t first_rt) const {
  ChangeBatch& b = d.batch;
  for (const NodeChange& n : b.nodes) {
    if (n.kind != ChangeKind::kUpdated) continue;
    std::vector<Symbol> names;
    for (Symbol a : n.attrs)
      if (a.str().starts_with(kRtAttrPrefix)) names.emplace_back(a.str().substr(kRtAttrPrefix.size()));
    if (names.empty()) continue;
    const NodeRec* c = find_node(n.id);
    const NodeId parent = c ? rt_view(*c).parent : NodeId{};
    if (parent.is_null()) continue;
    const EdgeKey key{parent, n.id, symbols::rt()};
    auto same = std::find_if(b.edges.begin() + static_cast<std::ptrdiff_t>(first_rt), b.edges.end(),
                             [&](const EdgeChange& e) { return e.key == key && e.kind != ChangeKind::kDeleted; });
    if (same == b.edges.end()) {
      d.add_edge(key, ChangeKind::kUpdated).attrs = std::move(names);
    } else if (same->kind == ChangeKind::kUpdated) {
      same->attrs.insert(same->attrs.end(), names.begin(), names.end());
    }
  }
}

void Graph::Impl::save_last(NodeRec* r) {
  if (!tracker.enabled || !r->alive) return;
  auto* t = tracker.touch_node(r->id, r->alive, r->type);
  if (!t->last_saved) {
    t->last_saved = true;
    t->last_name = visible_name(*r);
    t->last_values = winning_values(r->attrs);
  }
  for (EdgeRec* e : r->incident()) save_last(*e);
}

void Graph::Impl::save_last(const EdgeRec& e) {
  if (!tracker.enabled || !edge_visible(e)) return;
  touch_edge(e);
  auto* t = tracker.find_edge_touch(e.key);
  if (t != nullptr && !t->last_saved) {
    t->last_saved = true;
    t->last_values = winning_values(e.attrs);
  }
}

void Graph::Impl::touch_incident_edges(NodeRec* r) {
  if (!tracker.enabled) return;
  for (EdgeRec* e : r->out) touch_edge(*e);
  for (EdgeRec* e : r->in) touch_edge(*e);  // a self-loop again: touching is idempotent
}

void Graph::Impl::Dispatch::recycle() {
  for (NodeChange& c : batch.nodes) spare_nodes.push_back(std::move(c));
  for (EdgeChange& c : batch.edges) spare_edges.push_back(std::move(c));
  batch.nodes.clear();
  batch.edges.clear();
}

namespace {
// A change appended to `into`: the last spare when there is one (its containers keep their capacity).
template <class Change>
Change& append_recycled(std::vector<Change>& into, std::vector<Change>& spares) {
  if (spares.empty()) return into.emplace_back();
  into.push_back(std::move(spares.back()));
  spares.pop_back();
  return into.back();
}
}  // namespace

NodeChange& Graph::Impl::Dispatch::add_node(NodeId id, ChangeKind kind, Symbol type) {
  NodeChange& c = append_recycled(batch.nodes, spare_nodes);
  c.id = id;
  c.kind = kind;
  c.type = type;
  c.attrs.clear();
  c.renamed = false;
  c.name.clear();
  c.values.clear();
  return c;
}

EdgeChange& Graph::Impl::Dispatch::add_edge(const EdgeKey& key, ChangeKind kind) {
  EdgeChange& c = append_recycled(batch.edges, spare_edges);
  c.key = key;
  c.kind = kind;
  c.attrs.clear();
  c.values.clear();
  return c;
}

void Graph::Impl::Dispatch::drop_last_node() {
  spare_nodes.push_back(std::move(batch.nodes.back()));
  batch.nodes.pop_back();
}

void Graph::Impl::Dispatch::drop_last_edge() {
  spare_edges.push_back(std::move(batch.edges.back()));
  batch.edges.pop_back();
}

void Graph::Impl::finish_tracking(bool local, ReplicaId origin,
                                  const std::vector<std::pair<NodeRec*, NodeRec*>>*) {
  if (!tracker.enabled) return;
  if (dispatch_depth == dispatches.size()) dispatches.push_back(std::make_unique<Dispatch>());
  Dispatch& d = *dispatches[dispatch_depth];
  d.recycle();
  ChangeBatch& b = d.batch;
  b.local = local;
  b.origin = origin;
  for (auto& t : tracker.nodes()) {
    const NodeRec* r = find_node(t.id);
    bool now = r && r->alive;
    if (!t.was_alive && now) {
      NodeChange& c = d.add_node(t.id, ChangeKind::kCreated, r->type);
      for (const AttrSlot& a : r->attrs)
        c.attrs.push_back(a.name);  // all of them, whenever they came
    } else if (t.was_alive && !now) {
      NodeChange& c = d.add_node(t.id, ChangeKind::kDeleted, t.type);
      c.name = std::move(t.last_name);
      c.values = std::move(t.last_values);
    } else if (now) {
      NodeChange& c = d.add_node(t.id, ChangeKind::kUpdated, r->type);
      for (const auto& [name, fp] : t.attrs)
        if (register_fingerprint(r->attrs, name) != fp) c.attrs.push_back(name);
      c.renamed = t.name_saved && visible_name(*r) != t.name_before;
      if (c.attrs.empty() && !c.renamed) d.drop_last_node();
    }
  }
  for (auto& t : tracker.edges()) {
    const EdgeRec* e = find_edge(t.edge);
    const bool now = e && edge_visible(*e);
    if (!t.was_visible && now) {
      EdgeChange& c = d.add_edge(t.edge, ChangeKind::kCreated);
      for (const AttrSlot& a : e->attrs) c.attrs.push_back(a.name);
    } else if (t.was_visible && !now) {
      d.add_edge(t.edge, ChangeKind::kDeleted).values = std::move(t.last_values);
    } else if (now) {
      EdgeChange& c = d.add_edge(t.edge, ChangeKind::kUpdated);
      for (const auto& [name, fp] : t.attrs)
        if (register_fingerprint(e->attrs, name) != fp) c.attrs.push_back(name);
      const bool version = t.version_saved && dots_fingerprint(e->exists) != t.version_before;
      if (c.attrs.empty() && !version) d.drop_last_edge();
    }
  }
  const std::size_t first_rt = b.edges.size();
  for (const auto& rt : tracker.rt_before()) {
    const NodeId child = rt.child;
    const RtView& before = rt.before;
    const NodeRec* c = find_node(child);
    const RtView after = c ? rt_view(*c) : RtView{};
    if (after == before) continue;
    if (before.parent != after.parent) {
      if (!before.parent.is_null())
        d.add_edge(EdgeKey{before.parent, child, symbols::rt()}, ChangeKind::kDeleted).values =
            last_rt_values(before, b.nodes, child, c);
      if (!after.parent.is_null())
        d.add_edge(EdgeKey{after.parent, child, symbols::rt()}, ChangeKind::kCreated).attrs.push_back(symbols::pose());
    } else if (!after.parent.is_null()) {
      d.add_edge(EdgeKey{after.parent, child, symbols::rt()}, ChangeKind::kUpdated).attrs.push_back(symbols::pose());
    }
  }
  report_rt_attrs(d, first_rt);
  tracker.reset();
  tracker.enabled = false;
  if (b.empty()) return;
  name_origin(origin, b.origin_name);
  // The subscribers at the start: one added by a callback hears the next batch; one removed by a
  // callback (marked until the dispatch ends) is not called again.
  ++dispatch_depth;
  const std::size_t n = subscribers.size();
  for (std::size_t i = 0; i < n; ++i)
    if (!subscribers[i].removed) subscribers[i].cb(b);
  if (--dispatch_depth == 0 && unsubscribed_in_dispatch) {
    unsubscribed_in_dispatch = false;
    std::erase_if(subscribers, [](const Subscriber& s) { return s.removed; });
  }
}

Graph::SubscriptionId Graph::subscribe(ChangeCallback cb) {
  SubscriptionId id = impl_->next_subscription++;
  impl_->subscribers.push_back(Impl::Subscriber{id, std::move(cb)});
  return id;
}

Graph::SubscriptionId Graph::subscribe(ChangeFilter filter, ChangeCallback cb) {
  if (filter.empty()) return subscribe(std::move(cb));
  return subscribe([filter = std::move(filter), cb = std::move(cb)](const ChangeBatch& b) {
    ChangeBatch part = filter.select(b);
    if (!part.empty()) cb(part);
  });
}

void Graph::set_origin_namer(OriginNamer namer) { impl_->origin_namer = std::move(namer); }

std::string Graph::origin_name(const ReplicaId& id) const {
  std::string name;
  impl_->name_origin(id, name);
  return name;
}

void Graph::unsubscribe(SubscriptionId id) {
  auto& s = impl_->subscribers;
  if (impl_->dispatch_depth == 0) return (void)std::erase_if(s, [&](const Impl::Subscriber& x) { return x.id == id; });
  for (Impl::Subscriber& x : s)
    if (x.id == id && !x.removed) {
      x.removed = true;
      impl_->unsubscribed_in_dispatch = true;
    }
}

}  // namespace quiver::graph
