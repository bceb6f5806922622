// Local changes: transactions, dot minting and delta recording.

#include <algorithm>
#include <unordered_map>
#include <unordered_set>

#include "quiver/graph/limits.h"

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
  for (EdgeRec* e : r->incident()) {
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

/// A transaction's bookkeeping: what it created, deleted and moved so far, for O(1) checks.
struct Transaction::Book {
  std::uint64_t epoch = 0;     // the graph's epoch its view was taken at
  bool open = false;           // counted in Graph::Impl::open_transactions
  std::uint64_t bytes = 0;     // estimated encoding of the delta
  std::vector<const void*> hints;             // node records found while validating, per op
  std::vector<std::uint64_t> reserved;        // counters handed out as node ids
  std::unordered_set<NodeId> created;
  std::unordered_set<NodeId> deleted;
  std::unordered_set<std::string> names;      // names taken by create_node
  std::unordered_map<EdgeKey, bool> edges;    // symbolic edges inserted (true) or deleted here
  std::unordered_map<NodeId, std::optional<NodeId>> parent;  // RT parent after this txn's moves
  std::unordered_set<NodeId> parents;         // nodes that gained an RT child here
};

namespace {
// Rough encoded size of one change, for the delta size limit.
std::uint64_t op_bytes(std::string_view a, std::string_view b = {}) { return 24 + a.size() + b.size(); }
std::uint64_t attrs_bytes(const std::vector<std::pair<Symbol, Value>>& attrs) {
  std::uint64_t n = 0;
  for (const auto& [k, v] : attrs) n += 16 + k.str().size() + v.payload_bytes();
  return n;
}
}  // namespace

Transaction::Transaction(Graph* g) : graph_(g), book_(std::make_unique<Book>()) {
  book_->epoch = g->impl_->epoch;
}
Transaction::Transaction(Transaction&&) noexcept = default;
Transaction& Transaction::operator=(Transaction&& o) noexcept {
  if (this != &o) {
    if (book_) release();
    graph_ = o.graph_;
    ops_ = std::move(o.ops_);
    book_ = std::move(o.book_);
  }
  return *this;
}
Transaction::~Transaction() {
  if (book_) release();
}

Transaction Graph::begin() { return Transaction(this); }
bool Graph::transaction_open() const { return impl_->open_transactions > 0; }

void Transaction::reserve(std::size_t ops) {
  ops_.reserve(ops_.size() + ops);
  book_->created.reserve(book_->created.size() + ops);
  book_->names.reserve(book_->names.size() + ops);
  book_->parent.reserve(book_->parent.size() + ops);
  book_->parents.reserve(book_->parents.size() + ops);
}

void Transaction::release() {
  Graph::Impl& g = *graph_->impl_;
  g.unreserve(book_->reserved);
  book_->reserved.clear();
  if (book_->open) {
    book_->open = false;
    --g.open_transactions;
  }
}

TxnOp& Transaction::record(TxnOp op) {
  if (!book_->open) {
    book_->open = true;
    ++graph_->impl_->open_transactions;
  }
  ops_.push_back(std::move(op));
  return ops_.back();
}

Status Transaction::add_bytes(const char* fn, std::uint64_t n) {
  if (book_->bytes + n > limits::kMaxDeltaBytes)
    return make_error(ErrorCode::kTooLarge, std::string(fn) + ": the transaction would encode to about " +
                                                std::to_string(book_->bytes + n) + " bytes (the limit is " +
                                                std::to_string(limits::kMaxDeltaBytes) + "); commit it in parts");
  book_->bytes += n;
  return {};
}

bool Transaction::node_usable(NodeId id) const {
  if (book_->deleted.count(id)) return false;
  return graph_->has_node(id) || book_->created.count(id) != 0;
}

bool Transaction::edge_usable(NodeId from, NodeId to, Symbol type) const {
  if (!node_usable(from) || !node_usable(to)) return false;
  auto it = book_->edges.find(EdgeKey{from, to, type});
  if (it != book_->edges.end()) return it->second;
  return graph_->has_edge(from, to, type);
}

Status Transaction::check_attrs(const char* fn, const std::vector<std::pair<Symbol, Value>>& attrs) const {
  for (const auto& [k, v] : attrs) {
    if (k.is_null()) return make_error(ErrorCode::kInvalidArgument, std::string(fn) + ": an attribute name is empty");
    if (Status s = check_name(std::string(fn) + ": the attribute name", k.str()); !s.ok()) return s;
    if (Status s = check_value(std::string(fn) + ": attribute '" + k.str() + "'", v); !s.ok()) return s;
  }
  return {};
}

Result<NodeId> Transaction::create_node(std::string_view type, std::string_view name,
                                        std::vector<std::pair<Symbol, Value>> attrs) {
  if (Status s = check_name("create_node(): the type", type); !s.ok()) return s.error();
  if (Status s = check_name("create_node(): the name", name); !s.ok()) return s.error();
  if (name.find('~') != std::string_view::npos)
    return make_error(ErrorCode::kInvalidArgument, "create_node(): name " + quote_name(name) + " contains '~' (reserved)");
  auto taken = graph_->find_node(name);
  const bool taken_now = taken && !book_->deleted.count(*taken);
  if (taken_now || book_->names.count(std::string(name)))
    return make_error(ErrorCode::kAlreadyExists, "create_node(): the name " + quote_name(name) + " is taken");
  if (Status s = check_attrs("create_node()", attrs); !s.ok()) return s.error();
  auto type_symbol = Symbol::make(type);
  if (!type_symbol.ok()) return make_error(type_symbol.error().code, "create_node(): " + type_symbol.error().message);
  Graph::Impl& g = *graph_->impl_;
  if (!g.can_mint(1)) return make_error(ErrorCode::kTooLarge, "create_node(): this replica's counter space is exhausted");
  if (Status s = add_bytes("create_node()", op_bytes(type, name) + attrs_bytes(attrs)); !s.ok()) return s.error();
  NodeId id{g.mint()};
  g.reserved.push_back(id.dot.counter);
  book_->reserved.push_back(id.dot.counter);
  TxnOp op{};
  op.kind = TxnOp::Kind::kCreateNode;
  op.node = id;
  op.type = *type_symbol;
  op.name = std::string(name);
  op.attrs = std::move(attrs);
  record(std::move(op));
  book_->created.insert(id);
  book_->names.emplace(name);
  return id;
}

Status Transaction::delete_node(NodeId id) {
  if (!node_usable(id)) return not_found("delete_node()", id);
  if (Status s = add_bytes("delete_node()", op_bytes({})); !s.ok()) return s;
  TxnOp op{};
  op.kind = TxnOp::Kind::kDeleteNode;
  op.node = id;
  record(std::move(op));
  book_->deleted.insert(id);
  return {};
}

Status Transaction::set(NodeId id, std::string_view attr, Value value) {
  auto a = Symbol::make(attr);
  if (!a.ok()) return make_error(a.error().code, "set(): " + a.error().message);
  return set(id, *a, std::move(value));
}

Status Transaction::set(NodeId id, Symbol attr, Value value) {
  const NodeRec* rec = book_->deleted.empty() ? graph_->impl_->visible_node(id) : nullptr;
  if (rec == nullptr && !node_usable(id)) return not_found("set()", id);
  if (attr.is_null()) return make_error(ErrorCode::kInvalidArgument, "set(): the attribute name is empty");
  if (Status s = check_name("set(): the attribute name", attr.str()); !s.ok()) return s;
  if (Status s = check_value("set(): attribute '" + attr.str() + "'", value); !s.ok()) return s;
  if (Status s = add_bytes("set()", op_bytes(attr.str()) + value.payload_bytes()); !s.ok()) return s;
  book_->hints.resize(ops_.size());
  book_->hints.push_back(rec);
  TxnOp op{};
  op.kind = TxnOp::Kind::kSetAttr;
  op.node = id;
  op.attr = attr;
  op.value = std::move(value);
  record(std::move(op));
  return {};
}

Status Transaction::remove_attr(NodeId id, Symbol attr) {
  if (!node_usable(id)) return not_found("remove_attr()", id);
  if (attr.is_null()) return make_error(ErrorCode::kInvalidArgument, "remove_attr(): the attribute name is empty");
  if (Status s = add_bytes("remove_attr()", op_bytes(attr.str())); !s.ok()) return s;
  TxnOp op{};
  op.kind = TxnOp::Kind::kRemoveAttr;
  op.node = id;
  op.attr = attr;
  record(std::move(op));
  return {};
}

namespace {
// Interns string-named attributes; the error names the function and the attribute.
Result<std::vector<std::pair<Symbol, Value>>> intern_attrs(
    const char* fn, std::initializer_list<std::pair<std::string_view, Value>> attrs) {
  std::vector<std::pair<Symbol, Value>> out;
  out.reserve(attrs.size());
  for (const auto& [name, value] : attrs) {
    auto s = Symbol::make(name);
    if (!s.ok()) return make_error(s.error().code, std::string(fn) + ": attribute '" + std::string(name) + "': " + s.error().message);
    out.emplace_back(*s, value);
  }
  return out;
}
}  // namespace

Result<NodeId> Transaction::create_node(std::string_view type, std::string_view name,
                                        std::initializer_list<std::pair<std::string_view, Value>> attrs) {
  auto a = intern_attrs("create_node()", attrs);
  if (!a.ok()) return a.error();
  return create_node(type, name, std::move(*a));
}

Status Transaction::insert_edge(NodeId from, NodeId to, std::string_view type,
                                std::initializer_list<std::pair<std::string_view, Value>> attrs) {
  auto a = intern_attrs("insert_edge()", attrs);
  if (!a.ok()) return a.error();
  return insert_edge(from, to, type, std::move(*a));
}

Status Transaction::insert_edge(NodeId from, NodeId to, std::string_view type,
                                std::vector<std::pair<Symbol, Value>> attrs) {
  auto t = Symbol::make(type);
  if (!t.ok()) return make_error(t.error().code, "insert_edge(): " + t.error().message);
  return insert_edge(from, to, *t, std::move(attrs));
}

Status Transaction::insert_edge(NodeId from, NodeId to, Symbol type, std::vector<std::pair<Symbol, Value>> attrs) {
  if (!node_usable(from)) return not_found("insert_edge()", from);
  if (!node_usable(to)) return not_found("insert_edge()", to);
  if (type.is_null()) return make_error(ErrorCode::kInvalidArgument, "insert_edge(): the edge type is empty");
  if (type == symbols::rt())
    return make_error(ErrorCode::kInvalidArgument, "insert_edge(): type 'RT' is reserved; use set_rt()");
  if (Status s = check_name("insert_edge(): the edge type", type.str()); !s.ok()) return s;
  if (Status s = check_attrs("insert_edge()", attrs); !s.ok()) return s;
  if (Status s = add_bytes("insert_edge()", op_bytes(type.str()) + attrs_bytes(attrs)); !s.ok()) return s;
  TxnOp op{};
  op.kind = TxnOp::Kind::kInsertEdge;
  op.node = from;
  op.other = to;
  op.type = type;
  op.attrs = std::move(attrs);
  record(std::move(op));
  book_->edges[EdgeKey{from, to, type}] = true;
  return {};
}

Status Transaction::delete_edge(NodeId from, NodeId to, Symbol type) {
  if (type == symbols::rt()) {
    bool known = false;
    std::optional<NodeId> p;
    if (auto it = book_->parent.find(to); it != book_->parent.end()) {
      known = true;
      p = it->second;
    }
    if (!known) p = graph_->rt_parent(to);
    if (!p || *p != from)
      return make_error(ErrorCode::kNotFound, "delete_edge(): no RT edge " + from.to_string() + " -> " + to.to_string());
    return remove_rt(to);
  }
  if (!edge_usable(from, to, type))
    return make_error(ErrorCode::kNotFound, "delete_edge(): no edge " + EdgeKey{from, to, type}.to_string());
  if (Status s = add_bytes("delete_edge()", op_bytes(type.str())); !s.ok()) return s;
  TxnOp op{};
  op.kind = TxnOp::Kind::kDeleteEdge;
  op.node = from;
  op.other = to;
  op.type = type;
  record(std::move(op));
  book_->edges[EdgeKey{from, to, type}] = false;
  return {};
}

Status Transaction::set_edge_attr(const EdgeKey& key, Symbol attr, Value value) {
  if (key.type == symbols::rt() || !edge_usable(key.from, key.to, key.type))
    return make_error(ErrorCode::kNotFound, "set_edge_attr(): no edge " + key.to_string());
  if (attr.is_null()) return make_error(ErrorCode::kInvalidArgument, "set_edge_attr(): the attribute name is empty");
  if (Status s = check_name("set_edge_attr(): the attribute name", attr.str()); !s.ok()) return s;
  if (Status s = check_value("set_edge_attr(): attribute '" + attr.str() + "'", value); !s.ok()) return s;
  if (Status s = add_bytes("set_edge_attr()", op_bytes(attr.str(), key.type.str()) + value.payload_bytes()); !s.ok())
    return s;
  TxnOp op{};
  op.kind = TxnOp::Kind::kSetEdgeAttr;
  op.node = key.from;
  op.other = key.to;
  op.type = key.type;
  op.attr = attr;
  op.value = std::move(value);
  record(std::move(op));
  return {};
}

Status Transaction::remove_edge_attr(const EdgeKey& key, Symbol attr) {
  if (key.type == symbols::rt() || !edge_usable(key.from, key.to, key.type))
    return make_error(ErrorCode::kNotFound, "remove_edge_attr(): no edge " + key.to_string());
  if (attr.is_null()) return make_error(ErrorCode::kInvalidArgument, "remove_edge_attr(): the attribute name is empty");
  if (Status s = add_bytes("remove_edge_attr()", op_bytes(attr.str(), key.type.str())); !s.ok()) return s;
  TxnOp op{};
  op.kind = TxnOp::Kind::kRemoveEdgeAttr;
  op.node = key.from;
  op.other = key.to;
  op.type = key.type;
  op.attr = attr;
  record(std::move(op));
  return {};
}

Status Transaction::cycle_check(NodeId parent, NodeId child) const {
  // A child with no RT children (in the replica or gained in this transaction) cannot be an
  // ancestor of its new parent: building a chain top-down never walks it.
  const NodeRec* c = graph_->impl_->visible_node(child);
  const bool has_children = (c != nullptr && !c->rt_children.empty()) || book_->parents.count(child) != 0;
  if (!has_children) return {};
  auto name = [&](NodeId n) {
    if (book_->created.count(n))
      for (const TxnOp& op : ops_)
        if (op.kind == TxnOp::Kind::kCreateNode && op.node == n) return "'" + op.name + "'";
    return "'" + graph_->name_of(n) + "'";
  };
  std::optional<NodeId> x = parent;
  for (std::size_t steps = 0; x; ++steps) {
    if (*x == child)
      return make_error(ErrorCode::kRefused, "set_rt(): putting " + name(child) + " under " + name(parent) +
                                                 " would close a cycle");
    if (steps > graph_->node_count() + ops_.size()) break;
    auto it = book_->parent.find(*x);
    x = it != book_->parent.end() ? it->second : graph_->rt_parent(*x);
  }
  return {};
}

Status Transaction::set_rt(NodeId parent, NodeId child, const Pose& X_PC, std::int64_t stamp) {
  if (!node_usable(parent)) return not_found("set_rt()", parent);
  if (!node_usable(child)) return not_found("set_rt()", child);
  if (parent == child)
    return make_error(ErrorCode::kInvalidArgument, "set_rt(): a node cannot be its own RT parent (" +
                                                       child.to_string() + ")");
  if (Status s = cycle_check(parent, child); !s.ok()) return s;
  if (Status s = add_bytes("set_rt()", 2 * sizeof(Pose) + 48); !s.ok()) return s;
  TxnOp op{};
  op.kind = TxnOp::Kind::kSetRt;
  op.node = child;
  op.other = parent;
  op.pose = X_PC;
  op.stamp = stamp;
  op.type = symbols::rt();
  record(std::move(op));
  book_->parent[child] = parent;
  book_->parents.insert(parent);
  return {};
}

Status Transaction::remove_rt(NodeId child) {
  if (!node_usable(child)) return not_found("remove_rt()", child);
  if (Status s = add_bytes("remove_rt()", 2 * sizeof(Pose) + 48); !s.ok()) return s;
  TxnOp op{};
  op.kind = TxnOp::Kind::kRemoveRt;
  op.node = child;
  op.type = symbols::rt();
  record(std::move(op));
  book_->parent[child] = std::nullopt;
  return {};
}

void Transaction::abort() {
  release();
  ops_.clear();
  Graph* g = graph_;
  book_ = std::make_unique<Book>();
  book_->epoch = g->impl_->epoch;
}

Status Transaction::revalidate() const {
  // Replays every change on a fresh view of the replica: the same checks, in the same order.
  Transaction t(graph_);
  for (const TxnOp& op : ops_) {
    Status s;
    switch (op.kind) {
      case TxnOp::Kind::kCreateNode: {
        auto taken = graph_->find_node(op.name);
        if ((taken && !t.book_->deleted.count(*taken)) || t.book_->names.count(op.name))
          s = make_error(ErrorCode::kAlreadyExists, "create_node(): the name " + quote_name(op.name) + " is taken");
        t.book_->created.insert(op.node);
        t.book_->names.insert(op.name);
        break;
      }
      case TxnOp::Kind::kDeleteNode: s = t.delete_node(op.node); break;
      case TxnOp::Kind::kSetAttr: s = t.set(op.node, op.attr, op.value); break;
      case TxnOp::Kind::kRemoveAttr: s = t.remove_attr(op.node, op.attr); break;
      case TxnOp::Kind::kInsertEdge: s = t.insert_edge(op.node, op.other, op.type, op.attrs); break;
      case TxnOp::Kind::kDeleteEdge: s = t.delete_edge(op.node, op.other, op.type); break;
      case TxnOp::Kind::kSetEdgeAttr: s = t.set_edge_attr(EdgeKey{op.node, op.other, op.type}, op.attr, op.value); break;
      case TxnOp::Kind::kRemoveEdgeAttr: s = t.remove_edge_attr(EdgeKey{op.node, op.other, op.type}, op.attr); break;
      case TxnOp::Kind::kSetRt: s = t.set_rt(op.other, op.node, op.pose, op.stamp); break;
      case TxnOp::Kind::kRemoveRt: s = t.remove_rt(op.node); break;
    }
    if (!s.ok())
      return make_error(s.error().code, "commit(): a change no longer applies (another commit or a merge came first): " +
                                            s.error().message);
  }
  return {};
}

Result<CommitInfo> Transaction::commit() {
  Graph::Impl& g = *graph_->impl_;
  CommitInfo info;
  info.ops = ops_.size();
  if (ops_.empty()) return info;
  auto refuse = [&](Error e) -> Result<CommitInfo> {
    g.out.rule.clear();
    g.out.binding.clear();
    abort();
    return e;
  };
  // Another commit or a merge since this transaction's calls: check them again.
  const bool stale = book_->epoch != g.epoch;
  if (stale)
    if (Status s = revalidate(); !s.ok()) return refuse(s.error());
  if (g.permission_check) {
    Status s = g.permission_check(*graph_, ops_);
    if (!s.ok()) return refuse(s.error());
  }
  if (g.validator) {
    Status s = g.validator(*graph_, ops_);  // may annotate g.out with the rule it matched
    if (!s.ok()) return refuse(s.error());
  }
  // Every dot this commit may mint must fit below the counter limit: refuse rather than wrap.
  std::uint64_t dots = 0;
  for (const TxnOp& op : ops_) dots += 2 + op.attrs.size();
  if (!g.can_mint(dots))
    return refuse(make_error(ErrorCode::kTooLarge, "commit(): this replica's counter space is exhausted"));
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
  std::vector<const void*>& hints = book_->hints;
  hints.resize(ops_.size());
  ++g.epoch;
  g.begin_tracking();
  if (g.out.nodes.empty() && g.out.edges.empty()) {
    g.out.kind = GraphDelta::Kind::kDelta;
    g.out.origin = g.self;
  }
  // This transaction's node ids are about to be published: no longer reserved.
  g.unreserve(book_->reserved);
  book_->reserved.clear();
  // Large transactions: grow the outgoing delta and the indexes once rather than step by step
  // (each step copies, and on a fresh heap every byte copied is a page to fault in).
  if (ops_.size() > 64) {
    g.out.nodes.reserve(g.out.nodes.size() + 2 * ops_.size());
    g.out.claims.reserve(g.out.claims.size() + ops_.size());
    g.out.samples.reserve(g.out.samples.size() + ops_.size());
  }
  if (book_->created.size() > 64) {
    const std::size_t more = book_->created.size();
    g.nodes.reserve(g.nodes.size() + more);
    g.by_name.reserve(g.by_name.size() + more);
    g.claimants.reserve(g.claimants.size() + more);
    g.claim_parent_refs.reserve(g.claim_parent_refs.size() + more);
  }
  for (std::uint32_t k : order) {
    TxnOp& op = ops_[k];
    NodeRec* n = !stale && hints[k] ? const_cast<NodeRec*>(static_cast<const NodeRec*>(hints[k])) : g.find_node(op.node);
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
  // A commit whose changes all turned out to be no-ops publishes nothing (a delta always changes
  // something); counters it skipped go out with the next commit that does.
  const bool changed = !g.out.nodes.empty() || !g.out.edges.empty();
  if (changed) g.publish_own_dots(info);
  if (g.rt_dirty) g.recompute_rt(nullptr);
  abort();  // the transaction is spent
  if (g.sink && changed) g.sink(g.out);
  g.out.clear();
  g.finish_tracking(true, g.self, nullptr);
  return info;
}

}  // namespace quiver::graph
