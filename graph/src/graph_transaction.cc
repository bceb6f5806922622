// Transactions: their bookkeeping, and each call (create, delete, set, edges, RT moves) checked
// against the replica and the transaction's own changes so far.

#include <algorithm>
#include <unordered_map>
#include <unordered_set>

#include "quiver/graph/limits.h"

#include "graph_impl.h"
#include "transaction_book.h"

namespace quiver::graph {
namespace {
Error not_found(const char* fn, NodeId id) {
  return make_error(ErrorCode::kNotFound, std::string(fn) + ": node " + id.to_string() + " does not exist");
}

// Rough encoded size of one change, for the delta size limit.
std::uint64_t op_bytes(std::string_view a, std::string_view b = {}) { return 24 + a.size() + b.size(); }
std::uint64_t attrs_bytes(const std::vector<std::pair<Symbol, Value>>& attrs) {
  std::uint64_t n = 0;
  for (const auto& [k, v] : attrs) n += 16 + k.str().size() + v.payload_bytes();
  return n;
}
}  // namespace

// A transaction takes the graph's spare book (and the capacity of the last one's ops) and gives
// it back when it ends: one transaction after another allocates nothing for its bookkeeping.
Transaction::Transaction(Graph* g) : graph_(g) {
  std::unique_ptr<Book>& spare = g->impl_->spare_book;
  if (spare) {
    book_ = std::move(spare);
    ops_.swap(book_->spare_ops);
  } else {
    book_ = std::make_unique<Book>();
  }
  book_->epoch = g->impl_->epoch;
}
Transaction::Transaction(Transaction&&) noexcept = default;
Transaction& Transaction::operator=(Transaction&& o) noexcept {
  if (this != &o) {
    if (book_) end();
    graph_ = o.graph_;
    ops_ = std::move(o.ops_);
    book_ = std::move(o.book_);
  }
  return *this;
}
Transaction::~Transaction() {
  if (book_) end();
}

void Transaction::end() {
  release();
  std::unique_ptr<Book>& spare = graph_->impl_->spare_book;
  if (spare) return;
  ops_.clear();
  book_->reset(0);
  book_->spare_ops.swap(ops_);
  spare = std::move(book_);
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
  if (const bool* here = book_->edges.find(EdgeKey{from, to, type})) return *here;
  return graph_->has_edge(from, to, type);
}

Status Transaction::check_attrs(const char* fn, const std::vector<std::pair<Symbol, Value>>& attrs) const {
  for (const auto& [k, v] : attrs) {
    if (k.is_null()) return make_error(ErrorCode::kInvalidArgument, std::string(fn) + ": an attribute name is empty");
    if (Status s = check_attribute(fn, k.str(), v); !s.ok()) return s;
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
  if (Status s = check_attribute("set()", attr.str(), value); !s.ok()) return s;
  // The attribute's visible value, from the node's record already at hand (a write's hot path).
  const Value* current = nullptr;
  if (const NodeRec* r = rec != nullptr ? rec : graph_->impl_->visible_node(id))
    if (const AttrSlot* slot = find_slot(r->attrs, attr))
      if (const auto* w = winner(slot->reg)) current = &w->value;
  if (Status s = type_kept("set()", current, value, id, attr, nullptr); !s.ok()) return s;
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

Status Transaction::type_kept(const char* fn, const Value* current, const Value& value, NodeId node, Symbol attr,
                              const EdgeKey* edge) const {
  if (current == nullptr || current->type() == value.type()) return {};
  const auto& allows = graph_->impl_->type_change_allowed;
  if (allows && allows(attr)) return {};
  // Removed earlier in this transaction: the write starts it afresh.
  for (auto op = ops_.rbegin(); op != ops_.rend(); ++op)
    if (op->node == node && op->attr == attr &&
        ((op->kind == TxnOp::Kind::kRemoveAttr && edge == nullptr) ||
         (op->kind == TxnOp::Kind::kRemoveEdgeAttr && edge != nullptr && op->other == edge->to && op->type == edge->type)))
      return {};
  const std::string what =
      "attribute '" + attr.str() + "' of " +
      (edge == nullptr ? "node '" + graph_->name_of(node) + "'"
                       : "edge '" + graph_->name_of(edge->from) + "' -[" + edge->type.str() + "]-> '" +
                             graph_->name_of(edge->to) + "'");
  return make_error(ErrorCode::kTypeMismatch, std::string(fn) + ": " + what + " holds a " + to_string(current->type()) +
                                                  "; a " + to_string(value.type()) +
                                                  " would change its type (remove it first in the same transaction, "
                                                  "or declare it \"any\" in the schema)");
}

bool Transaction::has_attr(NodeId id, Symbol attr) const {
  bool present = !graph_->attr_values(id, attr).empty();
  for (const TxnOp& op : ops_) {
    if (!(op.node == id)) continue;
    if (op.kind == TxnOp::Kind::kCreateNode)
      present = std::any_of(op.attrs.begin(), op.attrs.end(), [&](const auto& a) { return a.first == attr; });
    else if (op.kind == TxnOp::Kind::kSetAttr && op.attr == attr)
      present = true;
    else if (op.kind == TxnOp::Kind::kRemoveAttr && op.attr == attr)
      present = false;
  }
  return present;
}

Status Transaction::add(NodeId id, Symbol attr, Value value) {
  if (node_usable(id) && !attr.is_null() && has_attr(id, attr))
    return make_error(ErrorCode::kAlreadyExists, "add(): node '" + graph_->name_of(id) + "' already has the attribute '" +
                                                     attr.str() + "' (set() overwrites)");
  return set(id, attr, std::move(value));
}

Status Transaction::modify(NodeId id, Symbol attr, Value value) {
  if (node_usable(id) && !attr.is_null() && !has_attr(id, attr))
    return make_error(ErrorCode::kNotFound, "modify(): node '" + graph_->name_of(id) + "' has no attribute '" +
                                                attr.str() + "' (set() adds it)");
  return set(id, attr, std::move(value));
}

Result<bool> Transaction::remove_attr(NodeId id, Symbol attr) {
  if (!node_usable(id)) return not_found("remove_attr()", id);
  if (attr.is_null()) return make_error(ErrorCode::kInvalidArgument, "remove_attr(): the attribute name is empty");
  // Without it (as this transaction sees it) there is nothing to remove (and nothing to publish:
  // a remove takes away only the values it has seen).
  if (!has_attr(id, attr)) return false;
  if (Status s = add_bytes("remove_attr()", op_bytes(attr.str())); !s.ok()) return s.error();
  TxnOp op{};
  op.kind = TxnOp::Kind::kRemoveAttr;
  op.node = id;
  op.attr = attr;
  record(std::move(op));
  return true;
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

namespace {

// The nodes two names answer to, or kNotFound naming the first that answers to none.
Result<std::pair<NodeId, NodeId>> named_endpoints(const Graph& g, const char* what, std::string_view from,
                                                  std::string_view to) {
  const auto a = g.find_node(from);
  if (!a) return make_error(ErrorCode::kNotFound, std::string(what) + ": no node named '" + std::string(from) + "'");
  const auto b = g.find_node(to);
  if (!b) return make_error(ErrorCode::kNotFound, std::string(what) + ": no node named '" + std::string(to) + "'");
  return std::make_pair(*a, *b);
}

}  // namespace

Status Transaction::insert_edge(std::string_view from, std::string_view to, std::string_view type,
                                std::vector<std::pair<Symbol, Value>> attrs) {
  auto ends = named_endpoints(*graph_, "insert_edge()", from, to);
  if (!ends.ok()) return ends.error();
  return insert_edge(ends->first, ends->second, type, std::move(attrs));
}

Status Transaction::delete_edge(std::string_view from, std::string_view to, std::string_view type) {
  auto ends = named_endpoints(*graph_, "delete_edge()", from, to);
  if (!ends.ok()) return ends.error();
  const Symbol t = Symbol::find(type);  // a type never named has no edge
  if (t.is_null())
    return make_error(ErrorCode::kNotFound, "delete_edge(): no edge '" + std::string(from) + "' -[" + std::string(type) +
                                                "]-> '" + std::string(to) + "'");
  return delete_edge(ends->first, ends->second, t);
}

Status Transaction::insert_edge(NodeId from, NodeId to, Symbol type, std::vector<std::pair<Symbol, Value>> attrs) {
  if (!node_usable(from)) return not_found("insert_edge()", from);
  if (!node_usable(to)) return not_found("insert_edge()", to);
  if (type.is_null()) return make_error(ErrorCode::kInvalidArgument, "insert_edge(): the edge type is empty");
  if (type == symbols::rt()) {
    // An RT edge is made by set_rt() (it needs a pose); inserting it again replaces its attributes.
    if (!rt_parent_is(from, to))
      return make_error(ErrorCode::kInvalidArgument, "insert_edge(): an RT edge " + from.to_string() + " -> " +
                                                         to.to_string() +
                                                         " is made with set_rt(parent, child, pose, stamp); "
                                                         "insert_edge() then replaces its attributes");
    if (Status s = check_attrs("insert_edge()", attrs); !s.ok()) return s;
    for (Symbol a : graph_->edge_attr_names(EdgeKey{from, to, type}))
      if (std::none_of(attrs.begin(), attrs.end(), [&](const auto& kv) { return kv.first == a; }))
        if (auto r = remove_edge_attr(EdgeKey{from, to, type}, a); !r.ok()) return r.error();
    for (auto& [a, v] : attrs)
      if (Status s = set_edge_attr(EdgeKey{from, to, type}, a, std::move(v)); !s.ok()) return s;
    return {};
  }
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

bool Transaction::rt_parent_is(NodeId from, NodeId to) const {
  if (!node_usable(from) || !node_usable(to)) return false;
  std::optional<NodeId> p;
  if (const auto* moved = book_->parent.find(to)) p = *moved;
  else p = graph_->rt_parent(to);
  return p && *p == from;
}

Status Transaction::delete_edge(NodeId from, NodeId to, Symbol type) {
  if (type == symbols::rt()) {
    if (!rt_parent_is(from, to))
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
  if (key.type == symbols::rt()) {  // kept on the child as rt:<attr>
    if (!rt_parent_is(key.from, key.to))
      return make_error(ErrorCode::kNotFound, "set_edge_attr(): no edge " + key.to_string());
    if (attr.is_null()) return make_error(ErrorCode::kInvalidArgument, "set_edge_attr(): the attribute name is empty");
    auto name = Symbol::make(std::string(kRtAttrPrefix) + attr.str());
    if (!name.ok()) return make_error(name.error().code, "set_edge_attr(): " + name.error().message);
    return set(key.to, *name, std::move(value));
  }
  if (!edge_usable(key.from, key.to, key.type))
    return make_error(ErrorCode::kNotFound, "set_edge_attr(): no edge " + key.to_string());
  if (attr.is_null()) return make_error(ErrorCode::kInvalidArgument, "set_edge_attr(): the attribute name is empty");
  if (Status s = check_attribute("set_edge_attr()", attr.str(), value); !s.ok()) return s;
  if (Status s = type_kept("set_edge_attr()", graph_->edge_attr(key, attr), value, key.from, attr, &key); !s.ok())
    return s;
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

Result<bool> Transaction::remove_edge_attr(const EdgeKey& key, Symbol attr) {
  if (key.type == symbols::rt()) {
    if (!rt_parent_is(key.from, key.to))
      return make_error(ErrorCode::kNotFound, "remove_edge_attr(): no edge " + key.to_string());
    if (attr.is_null()) return make_error(ErrorCode::kInvalidArgument, "remove_edge_attr(): the attribute name is empty");
    const Symbol name = Symbol::find(std::string(kRtAttrPrefix) + attr.str());
    if (name.is_null()) return false;  // never named: no node has it
    return remove_attr(key.to, name);
  }
  if (!edge_usable(key.from, key.to, key.type))
    return make_error(ErrorCode::kNotFound, "remove_edge_attr(): no edge " + key.to_string());
  if (attr.is_null()) return make_error(ErrorCode::kInvalidArgument, "remove_edge_attr(): the attribute name is empty");
  // Whether the edge has it as this transaction sees it (as remove_attr()): the replica's values,
  // then this transaction's own writes of that edge in order (a re-insertion replaces them all).
  bool present = !graph_->edge_attr_values(key, attr).empty();
  for (const TxnOp& op : ops_) {
    if (!(op.node == key.from) || !(op.other == key.to) || !(op.type == key.type)) continue;
    if (op.kind == TxnOp::Kind::kInsertEdge)
      present = std::any_of(op.attrs.begin(), op.attrs.end(), [&](const auto& a) { return a.first == attr; });
    else if (op.kind == TxnOp::Kind::kDeleteEdge)
      present = false;
    else if ((op.kind == TxnOp::Kind::kSetEdgeAttr || op.kind == TxnOp::Kind::kRemoveEdgeAttr) && op.attr == attr)
      present = op.kind == TxnOp::Kind::kSetEdgeAttr;
  }
  if (!present) return false;
  if (Status s = add_bytes("remove_edge_attr()", op_bytes(attr.str(), key.type.str())); !s.ok()) return s.error();
  TxnOp op{};
  op.kind = TxnOp::Kind::kRemoveEdgeAttr;
  op.node = key.from;
  op.other = key.to;
  op.type = key.type;
  op.attr = attr;
  record(std::move(op));
  return true;
}

Status Transaction::cycle_check(NodeId parent, NodeId child) const {
  // A child with no RT children (in the replica or gained in this transaction) cannot be an
  // ancestor of its new parent: building a chain top-down never walks it.
  const NodeRec* c = graph_->impl_->visible_node(child);
  const bool has_children = (c != nullptr && !c->rt_children.empty()) || book_->parents.contains(child);
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
    const auto* moved = book_->parent.find(*x);
    x = moved != nullptr ? *moved : graph_->rt_parent(*x);
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
  book_->parents[parent] = true;
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

}  // namespace quiver::graph
