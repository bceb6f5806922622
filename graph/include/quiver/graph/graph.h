#pragma once
/// @file
/// The world-model replica: ONE causal delta-state CRDT holding typed nodes, typed multi-edges,
/// attribute registers and the kinematic (RT) tree, all sharing one causal context.
///
/// Semantics, in short:
///  - a node's id is its creation dot; deleting a node removes its attributes and every incident
///    edge it has seen; a concurrent attribute write never resurrects a deleted node;
///  - an edge (from, to, type) is add-wins against a concurrent delete, and is visible only
///    while both endpoints are;
///  - an attribute is a multi-value register: concurrent writes are all kept, `attr()` returns a
///    deterministic winner (greatest Lamport dot) and `attr_values()` shows the conflict;
///  - names are unique among visible nodes: a local create with a taken name is refused, and of
///    concurrently created namesakes the earliest (Lamport order) keeps the name while the
///    others read as "name~<id>";
///  - the RT tree: at most one parent per node and no cycle, whatever concurrent moves arrive
///    (the replicated-tree move operation: moves ordered by Lamport dot, a move that would close
///    a cycle is skipped and the node keeps the parent it had when the move was made).
///
/// Threading: a Graph is owned by one thread (its owner thread); every member of Graph and
/// Transaction must be called on it, and every callback the graph makes (subscribers, sinks,
/// validators, observers) runs on it. Nothing here blocks or spawns threads.
///
/// Errors: expected failures are returned as values (Result / Status, quiver/base/result.h).
/// The only exception thrown on purpose is std::length_error from the overloads that intern a
/// new name with Symbol(std::string_view) when the process's table of names is full; each says so.

#include <functional>
#include <initializer_list>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "quiver/crdt/causal_context.h"
#include "quiver/graph/delta.h"
#include "quiver/graph/changes.h"
#include "quiver/graph/ids.h"
#include "quiver/graph/symbol.h"
#include "quiver/graph/value.h"
#include "quiver/base/hash.h"
#include "quiver/base/result.h"

namespace quiver::graph {

class Graph;

/// One value of a register with the dot of the write that made it and its fencing epoch.
struct AttrValue {
  Value value;
  Dot dot;
  std::uint64_t fence = 0;  ///< the writer's lock epoch for the node's scope (0: unlocked)
};

/// An RT edge's attributes are its child's attributes of this prefix (Transaction::set_edge_attr()).
inline constexpr std::string_view kRtAttrPrefix = "rt:";

/// The current RT edge of a child: its parent and the latest pose.
struct RtEdge {
  NodeId parent;
  NodeId child;
  Pose pose;           ///< X_PC, the newest sample of the current move (or the move's own pose)
  std::int64_t stamp;  ///< stamp of `pose`
  Dot epoch;           ///< the move (claim) this edge comes from
};

/// A pending change inside a transaction, as a grammar or lock checker sees it.
struct TxnOp {
  enum class Kind : std::uint8_t {
    kCreateNode,
    kDeleteNode,
    kSetAttr,
    kRemoveAttr,
    kInsertEdge,
    kDeleteEdge,
    kSetEdgeAttr,
    kRemoveEdgeAttr,
    kSetRt,
    kRemoveRt,
  };
  Kind kind;
  NodeId node;   ///< the node; for edges, `from`; for RT, the child
  NodeId other;  ///< for edges, `to`; for RT, the parent
  Symbol type;   ///< node type or edge type
  Symbol attr;
  std::string name;  ///< node name (create)
  Value value;
  Pose pose;
  std::int64_t stamp = 0;
  std::vector<std::pair<Symbol, Value>> attrs;  ///< initial attributes (create node / insert edge)
};

/// What a commit published.
struct CommitInfo {
  std::size_t ops = 0;
  /// The lowest and highest counter of the dots this commit published (minted, or skipped by
  /// transactions that were abandoned); counters reserved by other open transactions may lie
  /// between them. Both 0 when nothing was published.
  std::uint64_t first_counter = 0;
  std::uint64_t last_counter = 0;
};

/// Batches local changes into one delta. Each call validates against the replica (plus the
/// transaction's own earlier changes) and the limits table (limits.h), and returns an error
/// without recording anything if the change is invalid. `commit()` applies everything
/// atomically, fires events and hands the delta to the graph's delta sink. A transaction not
/// committed is discarded.
///
/// Several transactions of one graph may be open at once and commit in any order: a node id
/// handed out by create_node() is reserved until its transaction commits or is discarded, and a
/// transaction whose view went stale (another commit or a merge happened since its calls) is
/// validated again at commit: if any of its changes no longer applies (a node it writes was
/// deleted, a name it takes was taken, a move now closes a cycle), commit() refuses the whole
/// transaction with an error naming the change, as if it had run after the other one.
///
/// "Visible to this transaction" below means: in the replica or created by this transaction, and
/// not deleted by it. Besides the codes each lists, every change method returns kTooLarge when
/// the transaction would encode to more than limits::kMaxDeltaBytes ("commit it in parts");
/// after an error the transaction stays usable.
///
/// Threading: used on the graph's owner thread only. A Transaction must not outlive its Graph; a
/// moved-from Transaction may only be destroyed or assigned to.
class Transaction {
 public:
  /// Takes over `other`'s changes and reserved node ids. Owner thread only.
  Transaction(Transaction&&) noexcept;
  /// Discards this transaction's own uncommitted changes (as the destructor does), then takes over
  /// `other`'s. Owner thread only.
  Transaction& operator=(Transaction&&) noexcept;
  /// Discards the changes (and releases the node ids it reserved) unless committed.
  /// Owner thread only.
  ~Transaction();

  /// Creates a node; its id is known at once (reserved until commit or discard). Fails if `name`
  /// is taken or empty. Owner thread only.
  /// @returns the new node's id, or kInvalidArgument (empty or non-UTF-8 type or name, a '~' in
  ///          the name, an empty attribute name), kAlreadyExists (a visible node not deleted by
  ///          this transaction, or one created earlier in it, has `name`), kTooLarge (a name or
  ///          value over the limits table, the table of names full, this replica's counter space
  ///          exhausted).
  Result<NodeId> create_node(std::string_view type, std::string_view name,
                             std::vector<std::pair<Symbol, Value>> attrs = {});
  /// The same with attributes named by strings: `create_node("mug", "mug1", {{"color", "red"}})`.
  /// Owner thread only.
  /// @returns as the Symbol overload; kTooLarge also when an attribute name cannot be interned.
  Result<NodeId> create_node(std::string_view type, std::string_view name,
                             std::initializer_list<std::pair<std::string_view, Value>> attrs);
  /// Deletes a node with its attributes, its incident edges and its RT edges. Owner thread only.
  /// @returns kNotFound if the node is not visible to this transaction (absent, or deleted by it).
  Status delete_node(NodeId id);
  /// Writes attribute `attr` of node `id`; the value supersedes every value the replica has seen
  /// (concurrent writes elsewhere survive as a conflict, see Graph::attr_values()). Owner thread
  /// only.
  /// @returns kNotFound (node not visible to this transaction), kInvalidArgument (`attr` null or
  ///          not UTF-8), kTooLarge (a name or value over the limits table), kTypeMismatch (the
  ///          attribute holds a value of another type: a write never changes it silently; remove
  ///          it first in this transaction, or let the schema allow it, Graph::set_type_change_check).
  Status set(NodeId id, Symbol attr, Value value);
  /// The same with the attribute named by a string (interned with Symbol::make()). Owner thread
  /// only.
  /// @returns as the Symbol overload (an empty `attr` is kInvalidArgument); kTooLarge also when
  ///          the table of names is full.
  Status set(NodeId id, std::string_view attr, Value value);
  /// DSR's add_attrib_local(): set() for an attribute the node does not have yet (as this
  /// transaction sees it). Owner thread only.
  /// @returns kAlreadyExists if it has it; otherwise as set().
  Status add(NodeId id, Symbol attr, Value value);
  /// DSR's modify_attrib_local(): set() for an attribute the node has (as this transaction sees
  /// it). Owner thread only.
  /// @returns kNotFound if it does not have it; otherwise as set().
  Status modify(NodeId id, Symbol attr, Value value);
  /// Removes attribute `attr` of node `id` (all its concurrent values) as this transaction sees it;
  /// removing one the node does not have is not an error and publishes nothing. Owner thread only.
  /// @returns true if the node had it (DSR's remove_attrib_local), false if not; kNotFound (node
  ///          not visible to this transaction), kInvalidArgument (`attr` null).
  Result<bool> remove_attr(NodeId id, Symbol attr);
  /// The same with the attribute named by a string. Owner thread only.
  /// @returns as the Symbol overload.
  /// @throws std::length_error if `attr` is a new name and the table of names is full.
  Result<bool> remove_attr(NodeId id, std::string_view attr) { return remove_attr(id, Symbol(attr)); }
  /// Inserts (or re-inserts, replacing its attributes) a symbolic edge. A self-loop (from == to) is a
  /// unary predicate, as in AGM and CORTEX files (docs/world-format.md). An RT edge is made by
  /// set_rt(); insert_edge() of an existing one replaces its attributes. Owner thread only.
  /// @returns kNotFound (`from` or `to` not visible to this transaction), kInvalidArgument (`type`
  ///          null, "RT" where `from` is not `to`'s parent, a name not UTF-8, an empty attribute
  ///          name), kTooLarge (a name or value over the limits table).
  Status insert_edge(NodeId from, NodeId to, Symbol type, std::vector<std::pair<Symbol, Value>> attrs = {});
  /// The same with the type named by a string (interned with Symbol::make()). Owner thread only.
  /// @returns as the Symbol overload; kTooLarge also when the table of names is full.
  Status insert_edge(NodeId from, NodeId to, std::string_view type,
                     std::vector<std::pair<Symbol, Value>> attrs = {});
  /// The same with attributes named by strings: `insert_edge(a, b, "in", {{"since", 4}})`.
  /// Owner thread only.
  /// @returns as the Symbol overload; kTooLarge also when a name cannot be interned.
  Status insert_edge(NodeId from, NodeId to, std::string_view type,
                     std::initializer_list<std::pair<std::string_view, Value>> attrs);
  /// Deletes the edge (from, to, type) with its attributes. With type "RT" it detaches `to` from
  /// its RT parent `from` (as remove_rt(to)). Owner thread only.
  /// @returns kNotFound if the edge is not visible to this transaction (for "RT": `from` is not
  ///          `to`'s RT parent).
  Status delete_edge(NodeId from, NodeId to, Symbol type);
  /// The same with the type named by a string. Owner thread only.
  /// @returns as the Symbol overload.
  /// @throws std::length_error if `type` is a new name and the table of names is full.
  Status delete_edge(NodeId from, NodeId to, std::string_view type) { return delete_edge(from, to, Symbol(type)); }
  /// By the endpoints' names (as Graph::find_node() resolves them), as DSR's
  /// insert_or_assign_edge and delete_edge(from_name, to_name, type) take them. Owner thread only.
  /// @returns kNotFound naming a name no visible node answers to; else as the NodeId overloads.
  Status insert_edge(std::string_view from, std::string_view to, std::string_view type,
                     std::vector<std::pair<Symbol, Value>> attrs = {});
  Status delete_edge(std::string_view from, std::string_view to, std::string_view type);
  /// Writes attribute `attr` of an edge. An RT edge's attributes (DSR's rt_covariance, custom
  /// ones) are kept on its child as `rt:<attr>`, as the importers keep a file's RT link
  /// attributes: they stay with the child when it moves. Owner thread only.
  /// @returns kNotFound (no such edge visible to this transaction; for "RT": `from` is not
  ///          `to`'s parent), kInvalidArgument (`attr` null or not UTF-8), kTooLarge (a name or
  ///          value over the limits table).
  Status set_edge_attr(const EdgeKey& key, Symbol attr, Value value);
  /// The same with the attribute named by a string. Owner thread only.
  /// @returns as the Symbol overload.
  /// @throws std::length_error if `attr` is a new name and the table of names is full.
  Status set_edge_attr(const EdgeKey& key, std::string_view attr, Value value) {
    return set_edge_attr(key, Symbol(attr), std::move(value));
  }
  /// Removes attribute `attr` of an edge (RT too) as this transaction sees it (lacking it is no error).
  /// @returns true if the edge had it (as remove_attr()), false if not; kNotFound (no such edge
  ///          visible to this transaction), kInvalidArgument (`attr` null). Owner thread only.
  Result<bool> remove_edge_attr(const EdgeKey& key, Symbol attr);
  /// The same with the attribute named by a string. Owner thread only.
  /// @returns as the Symbol overload.
  /// @throws std::length_error if `attr` is a new name and the table of names is full.
  Result<bool> remove_edge_attr(const EdgeKey& key, std::string_view attr) { return remove_edge_attr(key, Symbol(attr)); }
  /// Puts `child` under `parent` with transform X_PC at time `stamp`. If the child already hangs
  /// under `parent` this is a pose update (a new history sample); otherwise it is a move.
  /// Refused if it would close a cycle. Owner thread only.
  /// @returns kNotFound (`parent` or `child` not visible to this transaction), kInvalidArgument
  ///          (parent == child), kRefused (the move would close a cycle, counting this
  ///          transaction's earlier moves).
  Status set_rt(NodeId parent, NodeId child, const Pose& X_PC, std::int64_t stamp = 0);
  /// Detaches `child` from its RT parent (publishes nothing if it has none at commit).
  /// Owner thread only.
  /// @returns kNotFound if `child` is not visible to this transaction.
  Status remove_rt(NodeId child);

  /// Applies the changes as one delta. @returns what was published, or the error of the check
  /// that refused it (validators, a stale view that no longer applies, an exhausted counter
  /// space); a refused transaction changes nothing.
  ///
  /// In order: a transaction whose view went stale is checked again (the failing change's code,
  /// e.g. kNotFound, kAlreadyExists, kRefused); then the permission check and the commit
  /// validator run (their errors are returned as they are); kTooLarge if the counters to mint
  /// would pass crdt::kMaxCounter. On success the delta goes to the delta sink (only if it
  /// changes something) and then the subscribers run, all before commit() returns. An empty
  /// transaction returns CommitInfo{0, 0, 0} and runs no check. Either way the transaction is
  /// left empty and can be used again. Owner thread only.
  Result<CommitInfo> commit();
  /// Discards the changes made so far; the transaction can be used again. Owner thread only.
  void abort();

  /// Makes room for `ops` more changes at once (a loader that knows its size: a world file, a
  /// robot description), so a large transaction does not grow step by step. Owner thread only.
  void reserve(std::size_t ops);

  /// @returns true if no change is pending. Owner thread only.
  bool empty() const { return ops_.empty(); }
  /// @returns the number of pending changes. Owner thread only.
  std::size_t size() const { return ops_.size(); }
  /// @returns the pending changes, in call order. Owner thread only.
  const std::vector<TxnOp>& ops() const { return ops_; }
  /// @returns the graph this transaction writes to. Owner thread only.
  Graph& graph() { return *graph_; }

 private:
  friend class Graph;
  struct Book;
  explicit Transaction(Graph* g);
  bool node_usable(NodeId id) const;
  bool edge_usable(NodeId from, NodeId to, Symbol type) const;
  /// `from` is `to`'s RT parent as this transaction sees it.
  bool rt_parent_is(NodeId from, NodeId to) const;
  Status check_attrs(const char* fn, const std::vector<std::pair<Symbol, Value>>& attrs) const;
  Status cycle_check(NodeId parent, NodeId child) const;
  Status add_bytes(const char* fn, std::uint64_t n);
  /// Whether node `id` has attribute `attr` as this transaction sees it (the replica's values,
  /// then this transaction's own writes and removals in order).
  bool has_attr(NodeId id, Symbol attr) const;
  /// kTypeMismatch when `current` (the attribute's visible value, or null) has another type than
  /// `value` and neither the graph's type-change check nor a removal earlier in this transaction
  /// allows the change. `edge`: the edge whose attribute it is (null: node `node`'s).
  Status type_kept(const char* fn, const Value* current, const Value& value, NodeId node, Symbol attr,
                   const EdgeKey* edge) const;
  TxnOp& record(TxnOp op);
  Status revalidate() const;
  void release();
  /// release(), then the book (and the ops' capacity) goes back to the graph for the next one.
  void end();

  Graph* graph_;
  std::vector<TxnOp> ops_;
  std::unique_ptr<Book> book_;
};

/// Options fixed at construction.
struct GraphOptions {
  /// Build change events even when nobody subscribed (e.g. for tests).
  bool always_track_changes = false;
};

/// The replica. Reads see the visible state (nodes alive, edges whose endpoints both are);
/// pointers and spans they return stay valid until the next commit() or merge() on this graph.
/// Threading: owner thread only, for every member (see the file comment).
class Graph {
 public:
  /// An empty replica writing under id `self`. The one thread that then uses the graph is its
  /// owner thread (passing it to another thread needs a synchronizing handover).
  /// @pre No other replica, now or before, writes under `self` (their dots would collide): an
  ///      agent restarted without its state takes a new incarnation.
  explicit Graph(ReplicaId self, GraphOptions options = {});
  /// Owner thread only.
  /// @pre No Transaction of this graph is alive, and nothing holds a hook into it any more (a
  ///      Replicator must be destroyed first).
  ~Graph();
  Graph(const Graph&) = delete;
  Graph& operator=(const Graph&) = delete;

  /// @returns the id this replica writes under (the constructor's `self`). Owner thread only.
  const ReplicaId& replica() const;

  // ---- Reads (visible state) ----
  /// @returns true if `id` is a visible node. Owner thread only.
  bool has_node(NodeId id) const;
  /// @returns the number of visible nodes. Owner thread only.
  std::size_t node_count() const;
  /// @returns the visible nodes, sorted by id. Owner thread only.
  std::vector<NodeId> nodes() const;
  /// The visible node called `name`: a stored name resolves to its holder (the earliest of
  /// concurrent namesakes), "name~<id>" to the namesake with that id. Owner thread only.
  /// @returns the node, or nullopt if no visible node answers to `name`.
  std::optional<NodeId> find_node(std::string_view name) const;
  /// The name of a visible node (as name_of() gives it), or nullopt when the node is not visible
  /// (DSR's get_name_from_id gives nothing there; name_of() gives ""). Owner thread only.
  std::optional<std::string> find_name(NodeId id) const;
  /// The edge (from, to, type) by its endpoints' names, as DSR's get_edge(from, to, type) finds
  /// it. Owner thread only.
  /// @returns its key, or nullopt if a name answers to no visible node or the edge is not visible.
  std::optional<EdgeKey> find_edge(std::string_view from, std::string_view to, std::string_view type) const;
  /// @returns the visible nodes of type `type`, sorted by id (empty for the null symbol).
  /// Owner thread only.
  std::vector<NodeId> nodes_of_type(Symbol type) const;
  /// The same with the type named by a string. Owner thread only.
  /// @throws std::length_error if `type` is a new name and the table of names is full.
  std::vector<NodeId> nodes_of_type(std::string_view type) const { return nodes_of_type(Symbol(type)); }
  /// Type of a visible node (null symbol if absent). Owner thread only.
  Symbol type_of(NodeId id) const;
  /// Effective (unique) name of a visible node; empty if absent. Owner thread only.
  /// @returns the stored name, or "name~<id>" for a namesake that does not hold the name.
  std::string name_of(NodeId id) const;
  /// Visible nodes sharing the stored name `name` (more than one after concurrent creations).
  /// Owner thread only.
  /// @returns those nodes in Lamport order of their ids (the name's holder first); empty if none.
  std::vector<NodeId> namesakes(std::string_view name) const;

  /// The winning value of an attribute, or nullptr. Owner thread only.
  /// @returns the value with the greatest dot (Lamport order) of node `id`'s attribute `name`;
  ///          nullptr if the node is not visible or lacks it. Valid until the next commit or merge.
  const Value* attr(NodeId id, Symbol name) const;
  /// The same with the attribute named by a string. Owner thread only.
  /// @throws std::length_error if `name` is a new name and the table of names is full.
  const Value* attr(NodeId id, std::string_view name) const { return attr(id, Symbol(name)); }
  /// Typed read of a node attribute. @returns kNotFound naming the node or the attribute, or
  /// kTypeMismatch naming the requested and the stored type ("get<int64>(): attribute 'speed'
  /// of node 'robot' (id ...) is a string, not an int64"). Owner thread only; never throws
  /// (never interns `name`).
  template <class T>
  Result<T> get(NodeId id, std::string_view name) const {
    const Value* v = attr(id, Symbol::find(name));
    if (v == nullptr) return missing_attr_error(id, name);
    const T* p = v->get_if<T>();
    if (p == nullptr) return wrong_type_error(id, name, *v, value_type_of<T>);
    return *p;
  }
  /// Typed read of an edge attribute, with the same errors (naming the edge). Owner thread only.
  template <class T>
  Result<T> get(const EdgeKey& key, std::string_view name) const {
    const Value* v = edge_attr(key, Symbol::find(name));
    if (v == nullptr) return missing_attr_error(key, name);
    const T* p = v->get_if<T>();
    if (p == nullptr) return wrong_type_error(key, name, *v, value_type_of<T>);
    return *p;
  }
  /// All concurrent values of an attribute, winner first. Size > 1 means a conflict.
  /// Owner thread only.
  /// @returns empty if the node is not visible or lacks the attribute.
  std::vector<AttrValue> attr_values(NodeId id, Symbol name) const;
  /// @returns the names of node `id`'s attributes, sorted by text; empty if the node is not
  ///          visible. Owner thread only.
  std::vector<Symbol> attr_names(NodeId id) const;

  /// @returns true if the edge (from, to, type) is visible; for type "RT", if `from` is `to`'s
  ///          current RT parent. Owner thread only.
  bool has_edge(NodeId from, NodeId to, Symbol type) const;
  /// The same with the type named by a string (a name never interned matches nothing).
  /// Owner thread only.
  bool has_edge(NodeId from, NodeId to, std::string_view type) const { return has_edge(from, to, Symbol::find(type)); }
  /// Visible edges out of / into a node (RT edges included, type "RT"); `type` null = all.
  /// Owner thread only.
  /// @returns the edges sorted by canonical_less(); empty if the node is not visible.
  std::vector<EdgeKey> edges_from(NodeId id, Symbol type = {}) const;
  /// The same with the type named by a string (an empty string means all types).
  /// Owner thread only.
  /// @throws std::length_error if `type` is a new name and the table of names is full.
  std::vector<EdgeKey> edges_from(NodeId id, std::string_view type) const { return edges_from(id, typed(type)); }
  /// Visible edges into node `id`, as edges_from(). Owner thread only.
  std::vector<EdgeKey> edges_to(NodeId id, Symbol type = {}) const;
  /// The same with the type named by a string (an empty string means all types).
  /// Owner thread only.
  /// @throws std::length_error if `type` is a new name and the table of names is full.
  std::vector<EdgeKey> edges_to(NodeId id, std::string_view type) const { return edges_to(id, typed(type)); }
  /// @returns every visible edge of type `type` ("RT": every current RT edge), sorted by
  ///          canonical_less(). Owner thread only.
  std::vector<EdgeKey> edges_of_type(Symbol type) const;
  /// The same with the type named by a string (a name never interned matches nothing).
  /// Owner thread only.
  std::vector<EdgeKey> edges_of_type(std::string_view type) const;
  /// @returns the number of visible edges, RT edges included. Owner thread only.
  std::size_t edge_count() const;
  /// The greatest existence dot of a visible edge (its latest insertion), in Lamport order; for
  /// an RT edge, the epoch of the move. Nullopt if the edge is not visible. Owner thread only.
  std::optional<Dot> edge_version(const EdgeKey& key) const;
  /// The winning value of an edge attribute, as attr(). Owner thread only.
  /// @returns nullptr if the edge is not visible or lacks the attribute (an RT edge's are its
  ///          child's `rt:` attributes, set_edge_attr()).
  const Value* edge_attr(const EdgeKey& key, Symbol name) const;
  /// The same with the attribute named by a string (never interns it). Owner thread only.
  const Value* edge_attr(const EdgeKey& key, std::string_view name) const { return edge_attr(key, Symbol::find(name)); }
  /// All concurrent values of an edge attribute, winner first; empty if the edge is not visible
  /// or lacks it. Owner thread only.
  std::vector<AttrValue> edge_attr_values(const EdgeKey& key, Symbol name) const;
  /// @returns the names of the edge's attributes, sorted by text; empty if it is not visible.
  ///          Owner thread only.
  std::vector<Symbol> edge_attr_names(const EdgeKey& key) const;

  /// @returns the current RT parent of `child`, or nullopt if it is not visible or is a root.
  ///          Owner thread only.
  std::optional<NodeId> rt_parent(NodeId child) const;
  /// DSR's get_node_level(): how many RT edges lie between the node and its tree's root (0 for a
  /// root with children). Owner thread only.
  /// @returns nullopt if the node is not visible or is in no tree (no parent, no children).
  std::optional<std::size_t> rt_level(NodeId id) const;
  /// @returns the RT children of `parent`, sorted by id; empty if it is not visible.
  ///          Owner thread only.
  std::vector<NodeId> rt_children(NodeId parent) const;
  /// @returns the current RT edge of `child` (parent, newest pose of the current move), or
  ///          nullopt if it is not visible or has no parent. Owner thread only.
  std::optional<RtEdge> rt_edge(NodeId child) const;
  /// Stored samples of the child's RT edge, ascending by (stamp, dot); all epochs (at most
  /// kRtHistoryDepth). Owner thread only.
  /// @returns empty if `child` is not visible; valid until the next commit or merge.
  std::span<const RtSample> rt_history(NodeId child) const;
  /// Visible RT roots (visible nodes without an RT parent that have RT children), sorted by id.
  /// Owner thread only.
  std::vector<NodeId> rt_roots() const;

  // ---- Local writes ----
  /// @returns a new, empty transaction of this graph; several may be open at once.
  ///          Owner thread only.
  Transaction begin();
  /// True while a transaction of this graph holds uncommitted changes. Library code that writes
  /// on its own (lock claims, grammar repairs) checks it, so that it never commits inside a
  /// caller's transaction. Owner thread only.
  bool transaction_open() const;

  // ---- Replication ----
  /// Joins a delta (kDelta) or a state / context diff (kState). `delta` must come from the
  /// codec (already validated). Idempotent, commutative, associative.
  /// Merge observers run first, subscribers after the join; open transactions are checked again
  /// when they commit. Owner thread only.
  /// @pre `delta` was produced by decode() (which enforces the format's and the limits table's
  ///      rules) or by a Graph (delta sink, state(), state_diff()).
  void merge(const GraphDelta& delta);
  /// The whole state as a kState fragment. Owner thread only.
  GraphDelta state() const;
  /// A context diff: what a replica whose context is `theirs` lacks, plus the dots it must keep.
  /// Owner thread only.
  /// @returns a kState fragment carrying this replica's whole context.
  GraphDelta state_diff(const crdt::CausalContext& theirs) const;
  /// @returns the causal context: every dot this replica has seen (minted or merged). The
  ///          reference lives as long as the graph. Owner thread only.
  const crdt::CausalContext& context() const;
  /// Canonical digest of the whole CRDT state (store and context): equal on two replicas iff
  /// their states are equal. Owner thread only.
  Digest128 digest() const;

  /// Receives every delta this replica commits (the replicator installs itself here).
  /// Replaces the previous sink (null: none); called inside commit(), before the subscribers,
  /// only for a commit that changes something. Owner thread only.
  void set_delta_sink(std::function<void(const GraphDelta&)> sink);

  /// Observed just before a commit applies: return an error to refuse the transaction.
  using CommitValidator = std::function<Status(const Graph&, const std::vector<TxnOp>&)>;
  /// Installs the validator (replacing the previous one; null: none). It sees the graph before
  /// the commit and the transaction's changes; the error it returns is what commit() returns.
  /// Owner thread only.
  void set_commit_validator(CommitValidator v);
  /// A second check, run before the validator on every commit, that the grammar guard and the
  /// locks never replace: the agent's graph-level permissions (agents/rules/permissions). Null: none.
  /// Replaces the previous check. Owner thread only.
  void set_permission_check(CommitValidator v);
  /// Whether attribute `attr` may change its value type (e.g. the schema declares it "any").
  /// Without a check (null, the default), no write changes an existing attribute's type: set()
  /// and set_edge_attr() refuse it with kTypeMismatch. Replaces the previous check. Owner thread only.
  void set_type_change_check(std::function<bool(Symbol attr)> allows);
  /// Attaches a rule claim to the delta of the next (or in-progress) commit; typically called by
  /// a commit validator that matched the transaction to a rule. A refused commit drops it.
  /// Owner thread only.
  /// @returns kInvalidArgument / kTooLarge if a name breaks the limits table (nothing attached);
  ///          kTooLarge for more than limits::kMaxTable variables; kInvalidArgument for a
  ///          variable bound to the null node.
  Status annotate_commit(std::string rule, std::vector<std::pair<std::string, NodeId>> binding);
  /// Called at the start of every merge with the state before it and the incoming fragment
  /// (several observers may watch: a grammar guard, a recorder), in the order they were added.
  using MergeObserver = std::function<void(const Graph& before, const GraphDelta& incoming)>;
  using ObserverId = std::uint64_t;
  /// Adds a merge observer. Owner thread only.
  /// @returns its id, for remove_merge_observer().
  ObserverId add_merge_observer(MergeObserver o);
  /// Removes a merge observer; an unknown id is ignored. Owner thread only.
  void remove_merge_observer(ObserverId id);
  /// The fencing epoch local writes to a node's attributes carry (a lock module installs it;
  /// edge attributes take the greater of their endpoints'). Without a provider, writes carry 0.
  using FenceProvider = std::function<std::uint64_t(NodeId)>;
  /// Installs the provider (replacing the previous one; null: none), consulted at commit.
  /// Owner thread only.
  void set_fence_provider(FenceProvider f);

  // ---- Events ----
  using SubscriptionId = std::uint64_t;
  /// Calls `cb` (on the owner thread, after the change applied) with every non-empty batch a
  /// commit or a merge makes. Callbacks run synchronously inside commit() / merge(), in
  /// subscription order; one may unsubscribe (itself or another) while running.
  /// Owner thread only.
  /// @returns the subscription's id, for unsubscribe().
  SubscriptionId subscribe(ChangeCallback cb);
  /// Calls `cb` with the part of every batch that `filter` selects, when that part is not empty.
  /// An empty filter subscribes to everything. Owner thread only.
  /// @returns the subscription's id, for unsubscribe().
  SubscriptionId subscribe(ChangeFilter filter, ChangeCallback cb);
  /// Ends a subscription; an unknown id is ignored. Owner thread only.
  void unsubscribe(SubscriptionId id);
  /// Names the agent of a replica id for ChangeBatch::origin_name (a replicator installs one
  /// that knows what its peers announced). Without one, batches carry origin.to_string().
  /// The namer writes the name into its second argument, whose capacity is kept from batch to
  /// batch (assigning a name into it allocates nothing once it has held one as long).
  using OriginNamer = std::function<void(const ReplicaId&, std::string& name)>;
  /// Installs the namer (replacing the previous one; null: none). Owner thread only.
  void set_origin_namer(OriginNamer namer);
  /// @returns the agent behind `id` as the namer names it ("locked by planner"), else id.to_string().
  std::string origin_name(const ReplicaId& id) const;

  // ---- Checks and statistics ----
  /// Structural invariants; returns one message per violation (empty = all hold).
  /// Owner thread only; for tests and fuzzers (it walks the whole state).
  std::vector<std::string> check_invariants() const;
  struct Stats {
    std::size_t node_records = 0;  ///< including invisible placeholders
    std::size_t edge_records = 0;
    std::size_t entries = 0;       ///< register entries, existence dots and RT claims
    std::size_t samples = 0;
    std::size_t context_ranges = 0;
  };
  /// @returns the sizes of the stored state (records, entries, samples, context ranges).
  ///          Owner thread only.
  Stats stats() const;

 private:
  friend class Transaction;
  friend struct GraphAccess;  // graph_impl.h: the library's own free functions (state_parts.h)
  Error missing_attr_error(NodeId id, std::string_view name) const;
  Error wrong_type_error(NodeId id, std::string_view name, const Value& v, ValueType wanted) const;
  Error missing_attr_error(const EdgeKey& key, std::string_view name) const;
  Error wrong_type_error(const EdgeKey& key, std::string_view name, const Value& v, ValueType wanted) const;
  /// The symbol of an edge type for a filtered read: one never interned matches no edge (a
  /// null symbol would mean "every type").
  static Symbol typed(std::string_view type);

  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace quiver::graph
