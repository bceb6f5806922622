// Graph: reads, records, indexes and events.

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
std::vector<AttrValue> register_values(const crdt::DotFun<Value>& reg) {
  // Winner first: the registers' own order (crdt::entry_less), descending.
  std::vector<const crdt::Entry<Value>*> entries;
  for (const auto& e : reg) entries.push_back(&e);
  std::sort(entries.begin(), entries.end(),
            [](const auto* a, const auto* b) { return crdt::entry_less(*b, *a); });
  std::vector<AttrValue> out;
  out.reserve(entries.size());
  for (const auto* e : entries) out.push_back(AttrValue{e->value, e->dot, e->fence});
  return out;
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

namespace {
const NodeRec* name_winner(const crdt::SmallVec<NodeRec*, 1>& v) {
  const NodeRec* best = nullptr;
  for (const NodeRec* r : v)
    if (best == nullptr || crdt::lamport_less(r->id.dot, best->id.dot)) best = r;
  return best;
}
}  // namespace

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

// ---------------------------------------------------------------- events

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
  const AttrSlot* s = find_slot(attrs, name);
  if (s == nullptr) return 0;
  std::uint64_t fp = s->reg.size();
  for (const auto& e : s->reg) fp += mix64(hash_value(e.dot) ^ (e.fence * 0x9e3779b97f4a7c15ULL));
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
      b.nodes.push_back(NodeChange{t.id, ChangeKind::kDeleted, t.type, {}, false});
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
      b.edges.push_back(EdgeChange{t.key, ChangeKind::kDeleted, {}});
    } else if (now) {
      EdgeChange c{t.key, ChangeKind::kUpdated, {}};
      for (const auto& [name, fp] : t.attrs)
        if (register_fingerprint(e->attrs, name) != fp) c.attrs.push_back(name);
      const bool version = t.version_saved && dots_fingerprint(e->exists) != t.version_before;
      if (!c.attrs.empty() || version) b.edges.push_back(std::move(c));
    }
  }
  for (const auto& [child, before] : tracker.rt_before()) {
    const NodeRec* c = find_node(child);
    const RtView after = c ? rt_view(*c) : RtView{};
    if (after == before) continue;
    if (before.parent != after.parent) {
      if (!before.parent.is_null())
        b.edges.push_back(
            EdgeChange{EdgeKey{before.parent, child, symbols::rt()}, ChangeKind::kDeleted, {}});
      if (!after.parent.is_null())
        b.edges.push_back(EdgeChange{
            EdgeKey{after.parent, child, symbols::rt()}, ChangeKind::kCreated, {symbols::pose()}});
    } else if (!after.parent.is_null()) {
      b.edges.push_back(EdgeChange{
          EdgeKey{after.parent, child, symbols::rt()}, ChangeKind::kUpdated, {symbols::pose()}});
    }
  }
  tracker.reset();
  tracker.enabled = false;
  if (b.empty()) return;
  b.origin_name = origin_namer ? origin_namer(origin) : origin.to_string();
  // Copy: a callback may unsubscribe.
  auto subs = subscribers;
  for (auto& [id, cb] : subs) cb(b);
}

// ---------------------------------------------------------------- Graph: construction, reads

Graph::Graph(ReplicaId self, GraphOptions options) : impl_(std::make_unique<Impl>(self, options)) {}
Graph::~Graph() = default;

const ReplicaId& Graph::replica() const { return impl_->self; }

bool Graph::has_node(NodeId id) const { return impl_->visible_node(id) != nullptr; }
std::size_t Graph::node_count() const { return impl_->alive_count; }

std::vector<NodeId> Graph::nodes() const {
  std::vector<NodeId> out;
  out.reserve(impl_->alive_count);
  for (const auto& [id, r] : impl_->nodes)
    if (r.alive) out.push_back(id);
  std::sort(out.begin(), out.end());
  return out;
}

std::optional<NodeId> Graph::find_node(std::string_view name) const {
  auto it = impl_->by_name.find(std::string(name));
  if (it != impl_->by_name.end()) return name_winner(it->second)->id;
  // "name~id" addresses a namesake that lost its name.
  auto tilde = name.rfind('~');
  if (tilde == std::string_view::npos) return std::nullopt;
  auto base = impl_->by_name.find(std::string(name.substr(0, tilde)));
  if (base == impl_->by_name.end()) return std::nullopt;
  for (const NodeRec* r : base->second)
    if (r->id.to_string() == name.substr(tilde + 1)) return r->id;
  return std::nullopt;
}

std::vector<NodeId> Graph::nodes_of_type(Symbol type) const {
  std::vector<NodeId> out;
  auto it = impl_->by_type.find(type);
  if (it == impl_->by_type.end()) return out;
  for (const NodeRec* r : it->second) out.push_back(r->id);
  std::sort(out.begin(), out.end());
  return out;
}

Symbol Graph::type_of(NodeId id) const {
  const NodeRec* r = impl_->visible_node(id);
  return r ? r->type : Symbol();
}

std::string Graph::name_of(NodeId id) const {
  const NodeRec* r = impl_->visible_node(id);
  return r == nullptr ? std::string() : impl_->visible_name(*r);
}

std::vector<NodeId> Graph::namesakes(std::string_view name) const {
  std::vector<NodeId> out;
  auto it = impl_->by_name.find(std::string(name));
  if (it == impl_->by_name.end()) return out;
  for (const NodeRec* r : it->second) out.push_back(r->id);
  std::sort(out.begin(), out.end(),
            [](NodeId a, NodeId b) { return crdt::lamport_less(a.dot, b.dot); });
  return out;
}

const Value* Graph::attr(NodeId id, Symbol name) const {
  const NodeRec* r = impl_->visible_node(id);
  if (r == nullptr) return nullptr;
  const AttrSlot* s = find_slot(r->attrs, name);
  if (s == nullptr) return nullptr;
  const auto* w = winner(s->reg);
  return w ? &w->value : nullptr;
}

std::vector<AttrValue> Graph::attr_values(NodeId id, Symbol name) const {
  const NodeRec* r = impl_->visible_node(id);
  if (r == nullptr) return {};
  const AttrSlot* s = find_slot(r->attrs, name);
  return s ? register_values(s->reg) : std::vector<AttrValue>{};
}

std::vector<Symbol> Graph::attr_names(NodeId id) const {
  std::vector<Symbol> out;
  const NodeRec* r = impl_->visible_node(id);
  if (r == nullptr) return out;
  for (const AttrSlot& s : r->attrs)
    if (!s.reg.empty()) out.push_back(s.name);
  std::sort(out.begin(), out.end(), text_less);
  return out;
}

Error Graph::missing_attr_error(NodeId id, std::string_view name) const {
  const NodeRec* r = impl_->visible_node(id);
  if (r == nullptr)
    return make_error(ErrorCode::kNotFound, "get(): node " + id.to_string() + " does not exist");
  return make_error(ErrorCode::kNotFound, "get(): node '" + name_of(id) + "' has no attribute '" +
                                              std::string(name) + "'");
}

Error Graph::wrong_type_error(NodeId id, std::string_view name, const Value& v,
                              ValueType wanted) const {
  return make_error(ErrorCode::kTypeMismatch,
                    std::string("get<") + to_string(wanted) + ">(): attribute '" +
                        std::string(name) + "' of node '" + name_of(id) + "' (" + id.to_string() +
                        ") is " + Value::article(v.type()) + ", not " + Value::article(wanted));
}

namespace {
std::string describe_edge(const Graph& g, const EdgeKey& k) {
  return "edge '" + g.name_of(k.from) + "' -[" + k.type.str() + "]-> '" + g.name_of(k.to) + "'";
}
}  // namespace

Error Graph::missing_attr_error(const EdgeKey& key, std::string_view name) const {
  if (!has_edge(key.from, key.to, key.type))
    return make_error(ErrorCode::kNotFound, "get(): " + describe_edge(*this, key) +
                                                " does not exist (" + key.to_string() + ")");
  return make_error(ErrorCode::kNotFound, "get(): " + describe_edge(*this, key) +
                                              " has no attribute '" + std::string(name) + "'");
}

Error Graph::wrong_type_error(const EdgeKey& key, std::string_view name, const Value& v,
                              ValueType wanted) const {
  return make_error(ErrorCode::kTypeMismatch,
                    std::string("get<") + to_string(wanted) + ">(): attribute '" +
                        std::string(name) + "' of " + describe_edge(*this, key) + " is " +
                        Value::article(v.type()) + ", not " + Value::article(wanted));
}

Symbol Graph::typed(std::string_view type) { return Symbol(type); }

std::vector<EdgeKey> Graph::edges_of_type(std::string_view type) const {
  Symbol s = Symbol::find(type);
  if (s.is_null()) return {};  // never interned: no edge has it
  return edges_of_type(s);
}

bool Graph::has_edge(NodeId from, NodeId to, Symbol type) const {
  if (type == symbols::rt()) {
    auto p = rt_parent(to);
    return p && *p == from;
  }
  const EdgeRec* e = impl_->find_edge(EdgeKey{from, to, type});
  return e && impl_->edge_visible(*e);
}

std::vector<EdgeKey> Graph::edges_from(NodeId id, Symbol type) const {
  std::vector<EdgeKey> out;
  const NodeRec* r = impl_->visible_node(id);
  if (r == nullptr) return out;
  for (const EdgeRec* e : r->out)
    if ((type.is_null() || e->key.type == type) && impl_->edge_visible(*e)) out.push_back(e->key);
  if (type.is_null() || type == symbols::rt())
    for (const NodeRec* c : r->rt_children) out.push_back(EdgeKey{id, c->id, symbols::rt()});
  std::sort(out.begin(), out.end(), canonical_less);
  return out;
}

std::vector<EdgeKey> Graph::edges_to(NodeId id, Symbol type) const {
  std::vector<EdgeKey> out;
  const NodeRec* r = impl_->visible_node(id);
  if (r == nullptr) return out;
  for (const EdgeRec* e : r->in)
    if ((type.is_null() || e->key.type == type) && impl_->edge_visible(*e)) out.push_back(e->key);
  if ((type.is_null() || type == symbols::rt()) && r->rt_parent)
    out.push_back(EdgeKey{r->rt_parent->id, id, symbols::rt()});
  std::sort(out.begin(), out.end(), canonical_less);
  return out;
}

std::vector<EdgeKey> Graph::edges_of_type(Symbol type) const {
  std::vector<EdgeKey> out;
  if (type == symbols::rt()) {
    for (const auto& [id, r] : impl_->nodes)
      if (r.alive && r.rt_parent) out.push_back(EdgeKey{r.rt_parent->id, id, type});
  } else {
    for (const auto& [k, e] : impl_->edges)
      if (k.type == type && impl_->edge_visible(e)) out.push_back(k);
  }
  std::sort(out.begin(), out.end(), canonical_less);
  return out;
}

std::size_t Graph::edge_count() const {
  std::size_t n = 0;
  for (const auto& [k, e] : impl_->edges) n += impl_->edge_visible(e) ? 1 : 0;
  for (const auto& [id, r] : impl_->nodes) n += (r.alive && r.rt_parent) ? 1 : 0;
  return n;
}

std::optional<Dot> Graph::edge_version(const EdgeKey& key) const {
  if (key.type == symbols::rt()) {
    const NodeRec* c = impl_->visible_node(key.to);
    if (c == nullptr || c->rt_parent == nullptr || !(c->rt_parent->id == key.from))
      return std::nullopt;
    return c->rt_epoch;
  }
  const EdgeRec* e = impl_->find_edge(key);
  if (e == nullptr || !impl_->edge_visible(*e)) return std::nullopt;
  Dot best;
  for (const Dot& d : e->exists)
    if (best.is_null() || crdt::lamport_less(best, d)) best = d;
  return best;
}

const Value* Graph::edge_attr(const EdgeKey& key, Symbol name) const {
  const EdgeRec* e = impl_->find_edge(key);
  if (e == nullptr || !impl_->edge_visible(*e)) return nullptr;
  const AttrSlot* s = find_slot(e->attrs, name);
  if (s == nullptr) return nullptr;
  const auto* w = winner(s->reg);
  return w ? &w->value : nullptr;
}

std::vector<AttrValue> Graph::edge_attr_values(const EdgeKey& key, Symbol name) const {
  const EdgeRec* e = impl_->find_edge(key);
  if (e == nullptr || !impl_->edge_visible(*e)) return {};
  const AttrSlot* s = find_slot(e->attrs, name);
  return s ? register_values(s->reg) : std::vector<AttrValue>{};
}

std::vector<Symbol> Graph::edge_attr_names(const EdgeKey& key) const {
  std::vector<Symbol> out;
  const EdgeRec* e = impl_->find_edge(key);
  if (e == nullptr || !impl_->edge_visible(*e)) return out;
  for (const AttrSlot& s : e->attrs)
    if (!s.reg.empty()) out.push_back(s.name);
  std::sort(out.begin(), out.end(), text_less);
  return out;
}

std::optional<NodeId> Graph::rt_parent(NodeId child) const {
  const NodeRec* r = impl_->visible_node(child);
  if (r == nullptr || r->rt_parent == nullptr) return std::nullopt;
  return r->rt_parent->id;
}

std::vector<NodeId> Graph::rt_children(NodeId parent) const {
  std::vector<NodeId> out;
  const NodeRec* r = impl_->visible_node(parent);
  if (r == nullptr) return out;
  for (const NodeRec* c : r->rt_children) out.push_back(c->id);
  std::sort(out.begin(), out.end());
  return out;
}

std::optional<RtEdge> Graph::rt_edge(NodeId child) const {
  const NodeRec* r = impl_->visible_node(child);
  if (r == nullptr || r->rt_parent == nullptr) return std::nullopt;
  return impl_->current_rt(*r);
}

std::span<const RtSample> Graph::rt_history(NodeId child) const {
  const NodeRec* r = impl_->visible_node(child);
  if (r == nullptr) return {};
  return {r->history.data(), r->history.size()};
}

std::vector<NodeId> Graph::rt_roots() const {
  std::vector<NodeId> out;
  for (const auto& [id, r] : impl_->nodes)
    if (r.alive && r.rt_parent == nullptr && !r.rt_children.empty()) out.push_back(id);
  std::sort(out.begin(), out.end());
  return out;
}

const crdt::CausalContext& Graph::context() const { return impl_->ctx; }

void Graph::set_delta_sink(std::function<void(const GraphDelta&)> sink) {
  impl_->sink = std::move(sink);
}
void Graph::set_commit_validator(CommitValidator v) { impl_->validator = std::move(v); }
void Graph::set_permission_check(CommitValidator v) { impl_->permission_check = std::move(v); }
void Graph::set_fence_provider(FenceProvider f) { impl_->fence_of = std::move(f); }
Graph::ObserverId Graph::add_merge_observer(MergeObserver o) {
  const ObserverId id = impl_->next_observer++;
  impl_->merge_observers.emplace_back(id, std::move(o));
  return id;
}
void Graph::remove_merge_observer(ObserverId id) {
  std::erase_if(impl_->merge_observers, [id](const auto& e) { return e.first == id; });
}
Status Graph::annotate_commit(std::string rule,
                              std::vector<std::pair<std::string, NodeId>> binding) {
  if (Status s = check_name("annotate_commit(): the rule name", rule); !s.ok()) return s;
  if (binding.size() > limits::kMaxTable)
    return make_error(ErrorCode::kTooLarge,
                      "annotate_commit(): " + std::to_string(binding.size()) + " variables");
  for (const auto& [var, id] : binding) {
    if (Status s = check_name("annotate_commit(): a variable name", var); !s.ok()) return s;
    if (id.is_null())
      return make_error(ErrorCode::kInvalidArgument,
                        "annotate_commit(): variable '" + var + "' is bound to no node");
  }
  impl_->out.rule = std::move(rule);
  impl_->out.binding = std::move(binding);
  return {};
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

void Graph::unsubscribe(SubscriptionId id) {
  auto& s = impl_->subscribers;
  s.erase(std::remove_if(s.begin(), s.end(), [&](const auto& p) { return p.first == id; }),
          s.end());
}

void Graph::merge(const GraphDelta& delta) {
  for (const auto& [id, observe] : impl_->merge_observers) observe(*this, delta);
  if (delta.kind == GraphDelta::Kind::kState)
    impl_->merge_state(delta);
  else
    impl_->merge_delta(delta);
}

}  // namespace quiver::graph
