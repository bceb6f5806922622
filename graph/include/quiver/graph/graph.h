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
/// Threading: a Graph is owned by one thread. Nothing here blocks or spawns threads.

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

enum class ChangeKind : std::uint8_t { kCreated, kUpdated, kDeleted };
const char* to_string(ChangeKind k);

/// A node created, deleted or updated. Updated means: the values of some attributes changed
/// (what attr_values() returns: a write, a removal, a concurrent value arriving or going), or its
/// visible name changed (an earlier namesake arrived, or the one that held the name left).
struct NodeChange {
  NodeId id;
  ChangeKind kind;
  Symbol type;
  /// kCreated: every attribute the node has; kUpdated: those whose values changed.
  std::vector<Symbol> attrs;
  bool renamed = false;  ///< kUpdated: name_of() now returns something else
};
/// An edge created, deleted or updated. A symbolic edge is updated when its attributes' values
/// or its version (edge_version(): a re-insert) changed; an RT edge when its current transform
/// or the pose history of its current move changed (attrs then holds "pose"). An RT edge that
/// changes parent is deleted under the old parent and created under the new one.
struct EdgeChange {
  EdgeKey key;  ///< RT edges appear with type symbols::rt(), from parent to child.
  ChangeKind kind;
  std::vector<Symbol> attrs;  ///< kCreated: every attribute; kUpdated: those that changed
};
/// Everything one commit or one merge changed in the visible graph.
struct ChangeBatch {
  bool local = false;
  ReplicaId origin;  ///< the replica whose change this is (this replica's id when local)
  /// The name of the agent whose change this is, as the graph's origin namer tells it (a
  /// replicator installs one that knows the names peers announce); origin.to_string() when the
  /// origin is unknown or no namer is installed.
  std::string origin_name;
  std::vector<NodeChange> nodes;
  std::vector<EdgeChange> edges;
  bool empty() const { return nodes.empty() && edges.empty(); }
};
using ChangeCallback = std::function<void(const ChangeBatch&)>;

/// Which changes a subscription cares about: a node change whose node type is listed, an edge
/// change whose edge type is listed, or a node or edge change that names a listed attribute.
/// The lists are alternatives (a change passes if any list lets it through); an empty list lets
/// nothing through by itself, and a filter with all lists empty lets everything through.
struct ChangeFilter {
  std::vector<std::string> node_types;
  std::vector<std::string> edge_types;
  std::vector<std::string> attributes;

  bool empty() const { return node_types.empty() && edge_types.empty() && attributes.empty(); }
  /// The part of `b` this filter lets through (origin and locality copied). Empty when nothing
  /// matches.
  ChangeBatch select(const ChangeBatch& b) const;
};

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
/// Threading: used on the graph's owner thread only.
class Transaction {
 public:
  Transaction(Transaction&&) noexcept;
  Transaction& operator=(Transaction&&) noexcept;
  /// Discards the changes (and releases the node ids it reserved) unless committed.
  ~Transaction();

  /// Creates a node; its id is known at once. Fails if `name` is taken or empty.
  Result<NodeId> create_node(std::string_view type, std::string_view name,
                             std::vector<std::pair<Symbol, Value>> attrs = {});
  /// The same with attributes named by strings: `create_node("mug", "mug1", {{"color", "red"}})`.
  Result<NodeId> create_node(std::string_view type, std::string_view name,
                             std::initializer_list<std::pair<std::string_view, Value>> attrs);
  /// Deletes a node with its attributes, its incident edges and its RT edges.
  Status delete_node(NodeId id);
  Status set(NodeId id, Symbol attr, Value value);
  Status set(NodeId id, std::string_view attr, Value value);
  Status remove_attr(NodeId id, Symbol attr);
  Status remove_attr(NodeId id, std::string_view attr) { return remove_attr(id, Symbol(attr)); }
  /// Inserts (or re-inserts, replacing its attributes) a symbolic edge. A self-loop (from == to) is a
  /// unary predicate, as in AGM and CORTEX files (docs/world-format.md). The type "RT" is reserved
  /// for set_rt().
  Status insert_edge(NodeId from, NodeId to, Symbol type, std::vector<std::pair<Symbol, Value>> attrs = {});
  Status insert_edge(NodeId from, NodeId to, std::string_view type,
                     std::vector<std::pair<Symbol, Value>> attrs = {});
  /// The same with attributes named by strings: `insert_edge(a, b, "in", {{"since", 4}})`.
  Status insert_edge(NodeId from, NodeId to, std::string_view type,
                     std::initializer_list<std::pair<std::string_view, Value>> attrs);
  Status delete_edge(NodeId from, NodeId to, Symbol type);
  Status delete_edge(NodeId from, NodeId to, std::string_view type) { return delete_edge(from, to, Symbol(type)); }
  Status set_edge_attr(const EdgeKey& key, Symbol attr, Value value);
  Status set_edge_attr(const EdgeKey& key, std::string_view attr, Value value) {
    return set_edge_attr(key, Symbol(attr), std::move(value));
  }
  Status remove_edge_attr(const EdgeKey& key, Symbol attr);
  Status remove_edge_attr(const EdgeKey& key, std::string_view attr) { return remove_edge_attr(key, Symbol(attr)); }
  /// Puts `child` under `parent` with transform X_PC at time `stamp`. If the child already hangs
  /// under `parent` this is a pose update (a new history sample); otherwise it is a move.
  /// Refused if it would close a cycle.
  Status set_rt(NodeId parent, NodeId child, const Pose& X_PC, std::int64_t stamp = 0);
  /// Detaches `child` from its RT parent.
  Status remove_rt(NodeId child);

  /// Applies the changes as one delta. @returns what was published, or the error of the check
  /// that refused it (validators, a stale view that no longer applies, an exhausted counter
  /// space); a refused transaction changes nothing.
  Result<CommitInfo> commit();
  /// Discards the changes made so far; the transaction can be used again.
  void abort();

  /// Makes room for `ops` more changes at once (a loader that knows its size: a world file, a
  /// robot description), so a large transaction does not grow step by step.
  void reserve(std::size_t ops);

  bool empty() const { return ops_.empty(); }
  std::size_t size() const { return ops_.size(); }
  const std::vector<TxnOp>& ops() const { return ops_; }
  Graph& graph() { return *graph_; }

 private:
  friend class Graph;
  struct Book;
  explicit Transaction(Graph* g);
  bool node_usable(NodeId id) const;
  bool edge_usable(NodeId from, NodeId to, Symbol type) const;
  Status check_attrs(const char* fn, const std::vector<std::pair<Symbol, Value>>& attrs) const;
  Status cycle_check(NodeId parent, NodeId child) const;
  Status add_bytes(const char* fn, std::uint64_t n);
  TxnOp& record(TxnOp op);
  Status revalidate() const;
  void release();

  Graph* graph_;
  std::vector<TxnOp> ops_;
  std::unique_ptr<Book> book_;
};

/// Options fixed at construction.
struct GraphOptions {
  /// Build change events even when nobody subscribed (e.g. for tests).
  bool always_track_changes = false;
};

class Graph {
 public:
  explicit Graph(ReplicaId self, GraphOptions options = {});
  ~Graph();
  Graph(const Graph&) = delete;
  Graph& operator=(const Graph&) = delete;

  const ReplicaId& replica() const;

  // ---- Reads (visible state) ----
  bool has_node(NodeId id) const;
  std::size_t node_count() const;
  std::vector<NodeId> nodes() const;
  std::optional<NodeId> find_node(std::string_view name) const;
  std::vector<NodeId> nodes_of_type(Symbol type) const;
  std::vector<NodeId> nodes_of_type(std::string_view type) const { return nodes_of_type(Symbol(type)); }
  /// Type of a visible node (null symbol if absent).
  Symbol type_of(NodeId id) const;
  /// Effective (unique) name of a visible node; empty if absent.
  std::string name_of(NodeId id) const;
  /// Visible nodes sharing the stored name `name` (more than one after concurrent creations).
  std::vector<NodeId> namesakes(std::string_view name) const;

  /// The winning value of an attribute, or nullptr.
  const Value* attr(NodeId id, Symbol name) const;
  const Value* attr(NodeId id, std::string_view name) const { return attr(id, Symbol(name)); }
  /// Typed read of a node attribute. @returns kNotFound naming the node or the attribute, or
  /// kTypeMismatch naming the requested and the stored type ("get<int64>(): attribute 'speed'
  /// of node 'robot' (id ...) is a string, not an int64").
  template <class T>
  Result<T> get(NodeId id, std::string_view name) const {
    const Value* v = attr(id, Symbol::find(name));
    if (v == nullptr) return missing_attr_error(id, name);
    const T* p = v->get_if<T>();
    if (p == nullptr) return wrong_type_error(id, name, *v, value_type_of<T>);
    return *p;
  }
  /// Typed read of an edge attribute, with the same errors (naming the edge).
  template <class T>
  Result<T> get(const EdgeKey& key, std::string_view name) const {
    const Value* v = edge_attr(key, Symbol::find(name));
    if (v == nullptr) return missing_attr_error(key, name);
    const T* p = v->get_if<T>();
    if (p == nullptr) return wrong_type_error(key, name, *v, value_type_of<T>);
    return *p;
  }
  /// All concurrent values of an attribute, winner first. Size > 1 means a conflict.
  std::vector<AttrValue> attr_values(NodeId id, Symbol name) const;
  std::vector<Symbol> attr_names(NodeId id) const;

  bool has_edge(NodeId from, NodeId to, Symbol type) const;
  bool has_edge(NodeId from, NodeId to, std::string_view type) const { return has_edge(from, to, Symbol::find(type)); }
  /// Visible edges out of / into a node (RT edges included, type "RT"); `type` null = all.
  std::vector<EdgeKey> edges_from(NodeId id, Symbol type = {}) const;
  std::vector<EdgeKey> edges_from(NodeId id, std::string_view type) const { return edges_from(id, typed(type)); }
  std::vector<EdgeKey> edges_to(NodeId id, Symbol type = {}) const;
  std::vector<EdgeKey> edges_to(NodeId id, std::string_view type) const { return edges_to(id, typed(type)); }
  std::vector<EdgeKey> edges_of_type(Symbol type) const;
  std::vector<EdgeKey> edges_of_type(std::string_view type) const;
  std::size_t edge_count() const;
  /// The greatest existence dot of a visible edge (its latest insertion), in Lamport order; for
  /// an RT edge, the epoch of the move. Nullopt if the edge is not visible.
  std::optional<Dot> edge_version(const EdgeKey& key) const;
  const Value* edge_attr(const EdgeKey& key, Symbol name) const;
  const Value* edge_attr(const EdgeKey& key, std::string_view name) const { return edge_attr(key, Symbol::find(name)); }
  std::vector<AttrValue> edge_attr_values(const EdgeKey& key, Symbol name) const;
  std::vector<Symbol> edge_attr_names(const EdgeKey& key) const;

  std::optional<NodeId> rt_parent(NodeId child) const;
  std::vector<NodeId> rt_children(NodeId parent) const;
  std::optional<RtEdge> rt_edge(NodeId child) const;
  /// Stored samples of the child's RT edge, ascending by (stamp, dot); all epochs.
  std::span<const RtSample> rt_history(NodeId child) const;
  /// Visible RT roots (visible nodes without an RT parent that have RT children).
  std::vector<NodeId> rt_roots() const;

  // ---- Local writes ----
  Transaction begin();
  /// True while a transaction of this graph holds uncommitted changes. Library code that writes
  /// on its own (lock claims, grammar repairs) checks it, so that it never commits inside a
  /// caller's transaction.
  bool transaction_open() const;

  // ---- Replication ----
  /// Joins a delta (kDelta) or a state / context diff (kState). `delta` must come from the
  /// codec (already validated). Idempotent, commutative, associative.
  void merge(const GraphDelta& delta);
  /// The whole state as a kState fragment.
  GraphDelta state() const;
  /// A context diff: what a replica whose context is `theirs` lacks, plus the dots it must keep.
  GraphDelta state_diff(const crdt::CausalContext& theirs) const;
  const crdt::CausalContext& context() const;
  /// Canonical digest of the whole CRDT state (store and context): equal on two replicas iff
  /// their states are equal.
  Digest128 digest() const;

  /// Receives every delta this replica commits (the replicator installs itself here).
  void set_delta_sink(std::function<void(const GraphDelta&)> sink);

  /// Observed just before a commit applies: return an error to refuse the transaction.
  using CommitValidator = std::function<Status(const Graph&, const std::vector<TxnOp>&)>;
  void set_commit_validator(CommitValidator v);
  /// A second check, run before the validator on every commit, that the grammar guard and the
  /// locks never replace: the agent's graph-level permissions (agents/rules/permissions). Null: none.
  void set_permission_check(CommitValidator v);
  /// Attaches a rule claim to the delta of the next (or in-progress) commit; typically called by
  /// a commit validator that matched the transaction to a rule.
  /// @returns kInvalidArgument / kTooLarge if a name breaks the limits table (nothing attached).
  Status annotate_commit(std::string rule, std::vector<std::pair<std::string, NodeId>> binding);
  /// Called at the start of every merge with the state before it and the incoming fragment
  /// (several observers may watch: a grammar guard, a recorder), in the order they were added.
  using MergeObserver = std::function<void(const Graph& before, const GraphDelta& incoming)>;
  using ObserverId = std::uint64_t;
  ObserverId add_merge_observer(MergeObserver o);
  void remove_merge_observer(ObserverId id);
  /// The fencing epoch local writes to a node's attributes carry (a lock module installs it;
  /// edge attributes take the greater of their endpoints'). Without a provider, writes carry 0.
  using FenceProvider = std::function<std::uint64_t(NodeId)>;
  void set_fence_provider(FenceProvider f);

  // ---- Events ----
  using SubscriptionId = std::uint64_t;
  /// Calls `cb` (on the owner thread, after the change applied) with every non-empty batch a
  /// commit or a merge makes.
  SubscriptionId subscribe(ChangeCallback cb);
  /// Calls `cb` with the part of every batch that `filter` selects, when that part is not empty.
  SubscriptionId subscribe(ChangeFilter filter, ChangeCallback cb);
  void unsubscribe(SubscriptionId id);
  /// Names the agent of a replica id for ChangeBatch::origin_name (a replicator installs one
  /// that knows what its peers announced). Without one, batches carry origin.to_string().
  using OriginNamer = std::function<std::string(const ReplicaId&)>;
  void set_origin_namer(OriginNamer namer);

  // ---- Checks and statistics ----
  /// Structural invariants; returns one message per violation (empty = all hold).
  std::vector<std::string> check_invariants() const;
  struct Stats {
    std::size_t node_records = 0;  ///< including invisible placeholders
    std::size_t edge_records = 0;
    std::size_t entries = 0;       ///< register entries, existence dots and RT claims
    std::size_t samples = 0;
    std::size_t context_ranges = 0;
  };
  Stats stats() const;

 private:
  friend class Transaction;
  friend struct GraphAccess;
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
