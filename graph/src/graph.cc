// Graph: construction, reads (nodes, attributes, edges, the RT tree) and the hooks around
// commits and merges (delta sink, validators, fences, merge observers).

#include <algorithm>

#include "graph_impl.h"
#include "quiver/graph/limits.h"

namespace quiver::graph {

namespace {
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

std::optional<std::string> Graph::find_name(NodeId id) const {
  const NodeRec* r = impl_->visible_node(id);
  if (r == nullptr) return std::nullopt;
  return impl_->visible_name(*r);
}

std::optional<EdgeKey> Graph::find_edge(std::string_view from, std::string_view to, std::string_view type) const {
  const auto a = find_node(from), b = find_node(to);
  const Symbol t = Symbol::find(type);
  if (!a || !b || t.is_null() || !has_edge(*a, *b, t)) return std::nullopt;
  return EdgeKey{*a, *b, t};
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

namespace {

// An RT edge's attribute `name`: its child's `rt:<name>` (never interned here: null if unknown).
Symbol rt_attr(Symbol name) {
  return name.is_null() ? Symbol() : Symbol::find(std::string(kRtAttrPrefix) + name.str());
}

}  // namespace

const Value* Graph::edge_attr(const EdgeKey& key, Symbol name) const {
  if (key.type == symbols::rt()) return has_edge(key.from, key.to, key.type) ? attr(key.to, rt_attr(name)) : nullptr;
  const EdgeRec* e = impl_->find_edge(key);
  if (e == nullptr || !impl_->edge_visible(*e)) return nullptr;
  const AttrSlot* s = find_slot(e->attrs, name);
  if (s == nullptr) return nullptr;
  const auto* w = winner(s->reg);
  return w ? &w->value : nullptr;
}

std::vector<AttrValue> Graph::edge_attr_values(const EdgeKey& key, Symbol name) const {
  if (key.type == symbols::rt())
    return has_edge(key.from, key.to, key.type) ? attr_values(key.to, rt_attr(name)) : std::vector<AttrValue>{};
  const EdgeRec* e = impl_->find_edge(key);
  if (e == nullptr || !impl_->edge_visible(*e)) return {};
  const AttrSlot* s = find_slot(e->attrs, name);
  return s ? register_values(s->reg) : std::vector<AttrValue>{};
}

std::vector<Symbol> Graph::edge_attr_names(const EdgeKey& key) const {
  std::vector<Symbol> out;
  if (key.type == symbols::rt()) {
    if (!has_edge(key.from, key.to, key.type)) return out;
    for (Symbol a : attr_names(key.to)) {
      const std::string& n = a.str();
      if (n.size() <= kRtAttrPrefix.size() || n.compare(0, kRtAttrPrefix.size(), kRtAttrPrefix) != 0) continue;
      if (auto s = Symbol::make(std::string_view(n).substr(kRtAttrPrefix.size())); s.ok()) out.push_back(*s);
    }
    std::sort(out.begin(), out.end(), text_less);
    return out;
  }
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

std::optional<std::size_t> Graph::rt_level(NodeId id) const {
  const NodeRec* r = impl_->visible_node(id);
  if (r == nullptr || (r->rt_parent == nullptr && r->rt_children.empty())) return std::nullopt;
  std::size_t level = 0;
  for (const NodeRec* p = r->rt_parent; p != nullptr; p = p->rt_parent) ++level;  // the tree has no cycles
  return level;
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
void Graph::set_type_change_check(std::function<bool(Symbol)> allows) { impl_->type_change_allowed = std::move(allows); }
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

void Graph::merge(const GraphDelta& delta) {
  for (const auto& [id, observe] : impl_->merge_observers) observe(*this, delta);
  if (delta.kind == GraphDelta::Kind::kState)
    impl_->merge_state(delta);
  else
    impl_->merge_delta(delta);
}

}  // namespace quiver::graph
