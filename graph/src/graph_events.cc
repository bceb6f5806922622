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
void Graph::Impl::report_rt_attrs(ChangeBatch& b, std::size_t first_rt) const {
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
      b.edges.push_back(EdgeChange{key, ChangeKind::kUpdated, std::move(names)});
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

void Graph::Impl::finish_tracking(bool local, ReplicaId origin,
                                  const std::vector<std::pair<NodeRec*, NodeRec*>>*) {
  if (!tracker.enabled) return;
  ChangeBatch b;
  b.local = local;
  b.origin = origin;
  for (auto& t : tracker.nodes()) {
    const NodeRec* r = find_node(t.id);
    bool now = r && r->alive;
    if (!t.was_alive && now) {
      NodeChange c{t.id, ChangeKind::kCreated, r->type, {}, false};
      for (const AttrSlot& a : r->attrs)
        c.attrs.push_back(a.name);  // all of them, whenever they came
      b.nodes.push_back(std::move(c));
    } else if (t.was_alive && !now) {
      NodeChange c{t.id, ChangeKind::kDeleted, t.type, {}, false, std::move(t.last_name), std::move(t.last_values)};
      b.nodes.push_back(std::move(c));
    } else if (now) {
      NodeChange c{t.id, ChangeKind::kUpdated, r->type, {}, false};
      for (const auto& [name, fp] : t.attrs)
        if (register_fingerprint(r->attrs, name) != fp) c.attrs.push_back(name);
      c.renamed = t.name_saved && visible_name(*r) != t.name_before;
      if (!c.attrs.empty() || c.renamed) b.nodes.push_back(std::move(c));
    }
  }
  for (auto& t : tracker.edges()) {
    const EdgeRec* e = find_edge(t.key);
    const bool now = e && edge_visible(*e);
    if (!t.was_visible && now) {
      EdgeChange c{t.key, ChangeKind::kCreated, {}};
      for (const AttrSlot& a : e->attrs) c.attrs.push_back(a.name);
      b.edges.push_back(std::move(c));
    } else if (t.was_visible && !now) {
      b.edges.push_back(EdgeChange{t.key, ChangeKind::kDeleted, {}, std::move(t.last_values)});
    } else if (now) {
      EdgeChange c{t.key, ChangeKind::kUpdated, {}};
      for (const auto& [name, fp] : t.attrs)
        if (register_fingerprint(e->attrs, name) != fp) c.attrs.push_back(name);
      const bool version = t.version_saved && dots_fingerprint(e->exists) != t.version_before;
      if (!c.attrs.empty() || version) b.edges.push_back(std::move(c));
    }
  }
  const std::size_t first_rt = b.edges.size();
  for (const auto& [child, before] : tracker.rt_before()) {
    const NodeRec* c = find_node(child);
    const RtView after = c ? rt_view(*c) : RtView{};
    if (after == before) continue;
    if (before.parent != after.parent) {
      if (!before.parent.is_null())
        b.edges.push_back(EdgeChange{EdgeKey{before.parent, child, symbols::rt()}, ChangeKind::kDeleted, {},
                                     last_rt_values(before, b.nodes, child, c)});
      if (!after.parent.is_null())
        b.edges.push_back(EdgeChange{
            EdgeKey{after.parent, child, symbols::rt()}, ChangeKind::kCreated, {symbols::pose()}});
    } else if (!after.parent.is_null()) {
      b.edges.push_back(EdgeChange{
          EdgeKey{after.parent, child, symbols::rt()}, ChangeKind::kUpdated, {symbols::pose()}});
    }
  }
  report_rt_attrs(b, first_rt);
  tracker.reset();
  tracker.enabled = false;
  if (b.empty()) return;
  b.origin_name = origin_namer ? origin_namer(origin) : origin.to_string();
  // Copy: a callback may unsubscribe.
  auto subs = subscribers;
  for (auto& [id, cb] : subs) cb(b);
}

Graph::SubscriptionId Graph::subscribe(ChangeCallback cb) {
  SubscriptionId id = impl_->next_subscription++;
  impl_->subscribers.emplace_back(id, std::move(cb));
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
  return impl_->origin_namer ? impl_->origin_namer(id) : id.to_string();
}

void Graph::unsubscribe(SubscriptionId id) {
  auto& s = impl_->subscribers;
  s.erase(std::remove_if(s.begin(), s.end(), [&](const auto& p) { return p.first == id; }),
          s.end());
}

}  // namespace quiver::graph
