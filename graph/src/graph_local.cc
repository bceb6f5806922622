// Local changes: transactions, dot minting and delta recording.

#include <algorithm>
#include <unordered_set>

#include "graph_impl.h"

namespace quiver::graph {
namespace {
enum Section { kHeader, kAttrs, kClaim, kSamples, kRemoved };

GraphDelta::Span open_span(std::size_t at) {
  return GraphDelta::Span{static_cast<std::uint32_t>(at), static_cast<std::uint32_t>(at)};
}
std::uint32_t u32(std::size_t n) { return static_cast<std::uint32_t>(n); }

Error not_found(const char* fn, NodeId id) {
  return make_error(ErrorCode::kNotFound, std::string(fn) + ": node " + id.to_string() + " does not exist");
}
}  // namespace

// ---------------------------------------------------------------- recording

Dot Graph::Impl::mint() {
  next_counter = std::max(next_counter, ctx.max_counter_overall()) + 1;
  return Dot{self, next_counter};
}

GraphDelta::NodeOp& Graph::Impl::out_node(NodeId id, int section) {
  if (!out.nodes.empty() && out.nodes.back().id == id) {
    auto& last = out.nodes.back();
    bool fits = false;
    switch (section) {
      case kHeader: fits = !last.has_header; break;
      case kAttrs:
        fits = last.attrs.end == out.attrs.size();
        break;
      case kClaim: fits = last.claim_added.empty() && last.claim_removed.empty(); break;
      case kSamples: fits = last.samples.end == out.samples.size(); break;
      case kRemoved: fits = true; break;
    }
    if (fits) {
      if (section == kAttrs && last.attrs.empty()) last.attrs = open_span(out.attrs.size());
      if (section == kSamples && last.samples.empty()) last.samples = open_span(out.samples.size());
      return last;
    }
  }
  GraphDelta::NodeOp op;
  op.id = id;
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
  auto& op = out_node(r->id, kAttrs);
  out.attrs.push_back(record_write(out, *slot, &d, &v, fence(r->id)));
  op.attrs.end = u32(out.attrs.size());
}

void Graph::Impl::local_remove_attr(NodeRec* r, Symbol name) {
  AttrSlot* slot = find_slot(r->attrs, name);
  if (slot == nullptr) return;
  touch_attr(r, name);
  auto& op = out_node(r->id, kAttrs);
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
  auto& op = out_node(id, kHeader);
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
  touch_node(r);
  touch_incident_edges(r);
  {
    auto& op = out_node(id, kRemoved);
    op.removed = true;
  }
  if (!r->attrs.empty()) {
    auto& op = out_node(id, kAttrs);
    record_attr_removals(out.attrs, r->attrs);
    op.attrs.end = u32(out.attrs.size());
  }
  if (!r->claim.empty()) {
    auto& op = out_node(id, kClaim);
    op.claim_removed = open_span(out.removed.size());
    for (const auto& e : r->claim) out.removed.push_back(e.dot);
    op.claim_removed.end = u32(out.removed.size());
  }
  std::vector<EdgeRec*> incident = r->out;
  incident.insert(incident.end(), r->in.begin(), r->in.end());
  for (EdgeRec* e : incident) {
    if (e->exists.empty() && e->attrs.empty()) continue;
    record_edge_removal(*e);
  }
  // RT edges to the children: remove the claims that name this node as parent.
  std::vector<NodeRec*> children = r->rt_children;
  for (NodeRec* c : children) {
    auto& op = out_node(c->id, kClaim);
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
  touch_edge(e);
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
  touch_edge(*e);
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
  auto& op = out_node(child->id, kClaim);
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
  auto& op = out_node(child->id, kSamples);
  out.samples.push_back(s);
  op.samples.end = u32(out.samples.size());
  return true;
}

void Graph::Impl::local_remove_rt(NodeRec* child) {
  if (rt_dirty) recompute_rt(nullptr);
  if (child->rt_parent == nullptr) return;
  local_set_rt(nullptr, child, Pose{}, 0);
}

// ---------------------------------------------------------------- Transaction

Transaction::Transaction(Graph* g) : graph_(g), epoch_(g->impl_->epoch) {}
Transaction::Transaction(Transaction&&) noexcept = default;
Transaction& Transaction::operator=(Transaction&&) noexcept = default;
Transaction::~Transaction() = default;

Transaction Graph::begin() { return Transaction(this); }

bool Transaction::node_usable(NodeId id) const {
  if (std::find(deleted_.begin(), deleted_.end(), id) != deleted_.end()) return false;
  if (graph_->has_node(id)) return true;
  return std::find(created_.begin(), created_.end(), id) != created_.end();
}

Result<NodeId> Transaction::create_node(std::string_view type, std::string_view name,
                                        std::vector<std::pair<Symbol, Value>> attrs) {
  if (type.empty()) return make_error(ErrorCode::kInvalidArgument, "create_node(): the type is empty");
  if (name.empty()) return make_error(ErrorCode::kInvalidArgument, "create_node(): the name is empty");
  if (name.find('~') != std::string_view::npos)
    return make_error(ErrorCode::kInvalidArgument,
                      "create_node(): name '" + std::string(name) + "' contains '~' (reserved)");
  auto taken = graph_->find_node(name);
  bool taken_now = taken && std::find(deleted_.begin(), deleted_.end(), *taken) == deleted_.end();
  if (taken_now || std::find(created_names_.begin(), created_names_.end(), name) != created_names_.end())
    return make_error(ErrorCode::kAlreadyExists, "create_node(): the name '" + std::string(name) + "' is taken");
  for (const auto& [k, v] : attrs)
    if (k.is_null()) return make_error(ErrorCode::kInvalidArgument, "create_node(): an attribute name is empty");
  NodeId id{graph_->impl_->mint()};
  TxnOp op{};
  op.kind = TxnOp::Kind::kCreateNode;
  op.node = id;
  op.type = Symbol(type);
  op.name = std::string(name);
  op.attrs = std::move(attrs);
  ops_.push_back(std::move(op));
  created_.push_back(id);
  created_names_.emplace_back(name);
  return id;
}

Status Transaction::delete_node(NodeId id) {
  if (!node_usable(id)) return not_found("delete_node()", id);
  TxnOp op{};
  op.kind = TxnOp::Kind::kDeleteNode;
  op.node = id;
  ops_.push_back(std::move(op));
  deleted_.push_back(id);
  return {};
}

Status Transaction::set(NodeId id, Symbol attr, Value value) {
  const NodeRec* rec = deleted_.empty() ? graph_->impl_->visible_node(id) : nullptr;
  if (rec == nullptr && !node_usable(id)) return not_found("set()", id);
  if (attr.is_null()) return make_error(ErrorCode::kInvalidArgument, "set(): the attribute name is empty");
  hints_.resize(ops_.size());
  hints_.push_back(rec);
  TxnOp& op = ops_.emplace_back();
  op.kind = TxnOp::Kind::kSetAttr;
  op.node = id;
  op.attr = attr;
  op.value = std::move(value);
  return {};
}

Status Transaction::remove_attr(NodeId id, Symbol attr) {
  if (!node_usable(id)) return not_found("remove_attr()", id);
  TxnOp op{};
  op.kind = TxnOp::Kind::kRemoveAttr;
  op.node = id;
  op.attr = attr;
  ops_.push_back(std::move(op));
  return {};
}

Status Transaction::insert_edge(NodeId from, NodeId to, Symbol type, std::vector<std::pair<Symbol, Value>> attrs) {
  if (!node_usable(from)) return not_found("insert_edge()", from);
  if (!node_usable(to)) return not_found("insert_edge()", to);
  if (from == to)
    return make_error(ErrorCode::kInvalidArgument, "insert_edge(): self-loops are not allowed (node " +
                                                       from.to_string() + ")");
  if (type.is_null()) return make_error(ErrorCode::kInvalidArgument, "insert_edge(): the edge type is empty");
  if (type == symbols::rt())
    return make_error(ErrorCode::kInvalidArgument, "insert_edge(): type 'RT' is reserved; use set_rt()");
  TxnOp op{};
  op.kind = TxnOp::Kind::kInsertEdge;
  op.node = from;
  op.other = to;
  op.type = type;
  op.attrs = std::move(attrs);
  ops_.push_back(std::move(op));
  return {};
}

namespace {
bool pending_edge(const std::vector<TxnOp>& ops, NodeId from, NodeId to, Symbol type) {
  bool present = false;
  for (const TxnOp& op : ops) {
    if (op.node != from || op.other != to || op.type != type) continue;
    if (op.kind == TxnOp::Kind::kInsertEdge) present = true;
    if (op.kind == TxnOp::Kind::kDeleteEdge) present = false;
  }
  return present;
}
}  // namespace

Status Transaction::delete_edge(NodeId from, NodeId to, Symbol type) {
  if (type == symbols::rt()) {
    auto p = graph_->rt_parent(to);
    if (!p || *p != from)
      return make_error(ErrorCode::kNotFound, "delete_edge(): no RT edge " + from.to_string() + " -> " + to.to_string());
    return remove_rt(to);
  }
  bool exists = graph_->has_edge(from, to, type) || pending_edge(ops_, from, to, type);
  if (!exists || !node_usable(from) || !node_usable(to))
    return make_error(ErrorCode::kNotFound, "delete_edge(): no edge " + EdgeKey{from, to, type}.to_string());
  TxnOp op{};
  op.kind = TxnOp::Kind::kDeleteEdge;
  op.node = from;
  op.other = to;
  op.type = type;
  ops_.push_back(std::move(op));
  return {};
}

Status Transaction::set_edge_attr(const EdgeKey& key, Symbol attr, Value value) {
  bool exists = graph_->has_edge(key.from, key.to, key.type) || pending_edge(ops_, key.from, key.to, key.type);
  if (!exists || key.type == symbols::rt())
    return make_error(ErrorCode::kNotFound, "set_edge_attr(): no edge " + key.to_string());
  if (attr.is_null()) return make_error(ErrorCode::kInvalidArgument, "set_edge_attr(): the attribute name is empty");
  TxnOp op{};
  op.kind = TxnOp::Kind::kSetEdgeAttr;
  op.node = key.from;
  op.other = key.to;
  op.type = key.type;
  op.attr = attr;
  op.value = std::move(value);
  ops_.push_back(std::move(op));
  return {};
}

Status Transaction::remove_edge_attr(const EdgeKey& key, Symbol attr) {
  bool exists = graph_->has_edge(key.from, key.to, key.type) || pending_edge(ops_, key.from, key.to, key.type);
  if (!exists) return make_error(ErrorCode::kNotFound, "remove_edge_attr(): no edge " + key.to_string());
  TxnOp op{};
  op.kind = TxnOp::Kind::kRemoveEdgeAttr;
  op.node = key.from;
  op.other = key.to;
  op.type = key.type;
  op.attr = attr;
  ops_.push_back(std::move(op));
  return {};
}

std::optional<NodeId> Transaction::pending_parent(NodeId child, bool* known) const {
  *known = false;
  std::optional<NodeId> p;
  for (const TxnOp& op : ops_) {
    if (op.node != child) continue;
    if (op.kind == TxnOp::Kind::kSetRt) {
      *known = true;
      p = op.other;
    } else if (op.kind == TxnOp::Kind::kRemoveRt) {
      *known = true;
      p.reset();
    }
  }
  return p;
}

Status Transaction::set_rt(NodeId parent, NodeId child, const Pose& X_PC, std::int64_t stamp) {
  if (!node_usable(parent)) return not_found("set_rt()", parent);
  if (!node_usable(child)) return not_found("set_rt()", child);
  if (parent == child)
    return make_error(ErrorCode::kInvalidArgument, "set_rt(): a node cannot be its own RT parent (" +
                                                       child.to_string() + ")");
  // Walk up from the parent through pending moves and the current tree: reaching the child
  // means the move would close a cycle.
  bool any_pending = false;
  for (const TxnOp& op : ops_) any_pending = any_pending || op.kind == TxnOp::Kind::kSetRt || op.kind == TxnOp::Kind::kRemoveRt;
  std::optional<NodeId> x = parent;
  for (std::size_t steps = 0; x; ++steps) {
    if (*x == child)
      return make_error(ErrorCode::kRefused, "set_rt(): putting " + graph_->name_of(child) + " under " +
                                                 graph_->name_of(parent) + " would close a cycle");
    if (steps > graph_->node_count() + ops_.size()) break;
    bool known = false;
    std::optional<NodeId> next;
    if (any_pending) next = pending_parent(*x, &known);
    x = known ? next : graph_->rt_parent(*x);
  }
  TxnOp op{};
  op.kind = TxnOp::Kind::kSetRt;
  op.node = child;
  op.other = parent;
  op.pose = X_PC;
  op.stamp = stamp;
  op.type = symbols::rt();
  ops_.push_back(std::move(op));
  return {};
}

Status Transaction::remove_rt(NodeId child) {
  if (!node_usable(child)) return not_found("remove_rt()", child);
  TxnOp op{};
  op.kind = TxnOp::Kind::kRemoveRt;
  op.node = child;
  op.type = symbols::rt();
  ops_.push_back(std::move(op));
  return {};
}

void Transaction::abort() {
  ops_.clear();
  hints_.clear();
  epoch_ = graph_->impl_->epoch;
  created_.clear();
  deleted_.clear();
  created_names_.clear();
}

Result<CommitInfo> Transaction::commit() {
  Graph::Impl& g = *graph_->impl_;
  CommitInfo info;
  info.ops = ops_.size();
  if (ops_.empty()) return info;
  if (g.validator) {
    Status s = g.validator(*graph_, ops_);  // may annotate g.out with the rule it matched
    if (!s.ok()) {
      g.out.rule.clear();
      g.out.binding.clear();
      abort();
      return s.error();
    }
  }
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
  const bool hints_valid = epoch_ == g.epoch;
  hints_.resize(ops_.size());
  ++g.epoch;
  g.begin_tracking();
  if (g.out.nodes.empty() && g.out.edges.empty()) {
    g.out.kind = GraphDelta::Kind::kDelta;
    g.out.origin = g.self;
  }
  const std::uint64_t first = g.published_max + 1;
  for (std::uint32_t k : order) {
    TxnOp& op = ops_[k];
    NodeRec* n = hints_valid && hints_[k] ? const_cast<NodeRec*>(static_cast<const NodeRec*>(hints_[k]))
                                          : g.find_node(op.node);
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
  if (g.next_counter >= first) {
    g.ctx.add_range(g.self, first, g.next_counter);
    g.out.context.add_range(g.self, first, g.next_counter);
    g.published_max = g.next_counter;
    info.first_counter = first;
    info.last_counter = g.next_counter;
  }
  // The local context also covers every dot this delta removed (they were ours to see already).
  if (g.rt_dirty) g.recompute_rt(nullptr);
  abort();  // the transaction is spent
  if (g.sink && !g.out.empty()) g.sink(g.out);
  g.out.clear();
  g.finish_tracking(true, g.self, nullptr);
  return info;
}

}  // namespace quiver::graph
