#pragma once
// Private: the records behind quiver::graph::Graph.

#include <algorithm>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "quiver/crdt/dot_store.h"
#include "quiver/crdt/small_vector.h"
#include "quiver/graph/graph.h"
#include "small_index.h"
#include "transaction_book.h"

namespace quiver::graph {

struct AttrSlot {
  Symbol name;
  crdt::DotFun<Value> reg;
};
using AttrList = std::vector<AttrSlot>;

AttrSlot* find_slot(AttrList& attrs, Symbol name);
const AttrSlot* find_slot(const AttrList& attrs, Symbol name);
/// The winning entry of a register: greatest (fence, Lamport dot).
template <class V>
const crdt::Entry<V>* winner(const crdt::DotFun<V>& reg) {
  const crdt::Entry<V>* best = nullptr;
  for (const auto& e : reg)
    if (best == nullptr || crdt::entry_less(*best, e)) best = &e;
  return best;
}

struct EdgeRec;

struct NodeRec {
  NodeId id;
  bool alive = false;  // the creation entry is present
  Symbol type;
  std::string name;
  AttrList attrs;
  std::vector<EdgeRec*> out;  // every edge record (visible or not) from / to this node
  std::vector<EdgeRec*> in;   // a self-loop (a unary predicate) is in both lists
  crdt::DotFun<RtClaim> claim;    // RT claims of this node as a child
  std::vector<RtSample> history;  // ascending by (stamp, dot), at most kRtHistoryDepth

  // Derived kinematic tree (recomputed from the claims).
  NodeRec* rt_parent = nullptr;
  std::vector<NodeRec*> rt_children;
  Dot rt_epoch;
  Pose rt_base_pose;
  std::int64_t rt_base_stamp = 0;

  bool is_empty_placeholder() const {
    return !alive && attrs.empty() && out.empty() && in.empty() && claim.empty() && history.empty();
  }
  /// Every edge record touching this node, a self-loop once.
  std::vector<EdgeRec*> incident() const;
};

struct EdgeRec {
  EdgeKey key;
  crdt::DotSet exists;
  AttrList attrs;
};

/// What a reader sees of a child's RT edge: its parent, its current transform, and the history
/// of its current move (as a fingerprint).
struct RtView {
  NodeId parent;  // null: no visible RT edge
  Dot epoch;
  Pose pose;
  std::int64_t stamp = 0;
  std::uint64_t history = 0;
  bool operator==(const RtView&) const = default;
};

/// Entries of one kind a batch touched, kept from batch to batch so that their containers keep
/// their capacity (a batch like the last one allocates nothing).
template <class Key, class Touch>
class TouchList {
 public:
  Touch* find(const Key& k) {
    const std::size_t i = index_.find(k, n_, [this](std::size_t j) { return items_[j].key(); });
    return i == SmallIndex<Key>::npos ? nullptr : &items_[i];
  }
  const Touch* find(const Key& k) const { return const_cast<TouchList*>(this)->find(k); }
  /// A fresh entry (recycled: its containers empty) for `k`, which find() did not find.
  Touch& add(const Key& k) {
    if (n_ == items_.size()) items_.emplace_back();
    Touch& t = items_[n_++];
    t.recycle(k);
    index_.added(k, n_, [this](std::size_t j) { return items_[j].key(); });
    return t;
  }
  std::span<Touch> items() { return {items_.data(), n_}; }
  void reset() {
    n_ = 0;
    index_.clear();
    if (items_.size() > kKeep) items_.resize(kKeep);
  }

 private:
  static constexpr std::size_t kKeep = 64;
  std::vector<Touch> items_;
  std::size_t n_ = 0;
  SmallIndex<Key> index_;
};

/// Collects what a commit or merge changed, to produce a ChangeBatch. Node and symbolic edge
/// changes are noted as they happen; RT edges are compared as a whole: the view of every child
/// whose kinematic state may change is saved before its first change in the batch, and
/// compared with its view at the end.
class ChangeTracker {
 public:
  bool enabled = false;

  void reset() {
    nodes_.reset();
    edges_.reset();
    rt_before_.reset();
  }
  // Attributes are compared by a fingerprint of their register (the values a reader sees),
  // saved before the first change in the batch.
  using AttrBefore = std::vector<std::pair<Symbol, std::uint64_t>>;
  using Values = std::vector<std::pair<Symbol, Value>>;
  struct NodeTouch {
    NodeId id;
    bool was_alive = false;
    Symbol type;
    AttrBefore attrs;
    bool name_saved = false;  // its visible name may change: name_before holds the old one
    std::string name_before;
    bool last_saved = false;  // it may be deleted: its name and values before (save_last())
    std::string last_name;
    Values last_values;
    const NodeId& key() const { return id; }
    void recycle(NodeId k) {
      id = k;
      attrs.clear();
      name_saved = last_saved = false;
      name_before.clear();
      last_name.clear();
      last_values.clear();
    }
  };
  struct EdgeTouch {
    EdgeKey edge;
    bool was_visible = false;
    AttrBefore attrs;
    bool version_saved = false;  // its existence dots may change: version_before fingerprints them
    std::uint64_t version_before = 0;
    bool last_saved = false;  // it may be deleted: its values before (save_last())
    Values last_values;
    const EdgeKey& key() const { return edge; }
    void recycle(const EdgeKey& k) {
      edge = k;
      attrs.clear();
      version_saved = last_saved = false;
      version_before = 0;
      last_values.clear();
    }
  };
  struct RtTouch {
    NodeId child;
    RtView before;
    const NodeId& key() const { return child; }
    void recycle(NodeId k) { child = k; }
  };
  NodeTouch* touch_node(NodeId id, bool was_alive, Symbol type) {
    if (NodeTouch* t = nodes_.find(id)) return t;
    NodeTouch& t = nodes_.add(id);
    t.was_alive = was_alive;
    t.type = type;
    return &t;
  }
  NodeTouch* find_node_touch(NodeId id) { return nodes_.find(id); }
  EdgeTouch* find_edge_touch(const EdgeKey& key) { return edges_.find(key); }
  bool node_was_alive(NodeId id, bool current) const {
    const NodeTouch* t = nodes_.find(id);
    return t == nullptr ? current : t->was_alive;
  }
  EdgeTouch* touch_edge(const EdgeKey& key, bool was_visible) {
    if (EdgeTouch* t = edges_.find(key)) return t;
    EdgeTouch& t = edges_.add(key);
    t.was_visible = was_visible;
    return &t;
  }
  bool edge_touched(const EdgeKey& key) const { return edges_.find(key) != nullptr; }
  /// True if `child`'s RT view was already saved in this batch.
  bool rt_saved(NodeId child) const { return rt_before_.find(child) != nullptr; }
  void save_rt(NodeId child, const RtView& v) {
    if (!rt_saved(child)) rt_before_.add(child).before = v;
  }

  std::span<NodeTouch> nodes() { return nodes_.items(); }
  std::span<EdgeTouch> edges() { return edges_.items(); }
  std::span<RtTouch> rt_before() { return rt_before_.items(); }

 private:
  TouchList<NodeId, NodeTouch> nodes_;
  TouchList<EdgeKey, EdgeTouch> edges_;
  TouchList<NodeId, RtTouch> rt_before_;
};

/// Fingerprints of a register and of an edge's version (its greatest existence dot), for change
/// detection.
std::uint64_t register_fingerprint(const AttrList& attrs, Symbol name);
std::uint64_t dots_fingerprint(const crdt::DotSet& dots);

/// Of concurrently created namesakes, the one that keeps the name: the earliest (Lamport order).
const NodeRec* name_winner(const crdt::SmallVec<NodeRec*, 1>& v);

inline void save_attr(ChangeTracker::AttrBefore& v, Symbol s, const AttrList& attrs) {
  for (const auto& [x, fp] : v)
    if (x == s) return;
  v.emplace_back(s, register_fingerprint(attrs, s));
}

/// What a replica whose context is `theirs` lacks of one record goes into `out` as ops (state
/// transfer, graph_state.cc); the dots it holds already go to out.keep.
void emit_node(NodeId id, const NodeRec& r, const crdt::CausalContext& theirs, GraphDelta& out);
void emit_edge(const EdgeKey& key, const EdgeRec& e, const crdt::CausalContext& theirs, GraphDelta& out);

/// Adds the dots of the entries a state holds (node creations, values, edge dots, claims, and
/// its keep list) to `held`.
void add_held(const GraphDelta& s, std::unordered_set<Dot>& held);

struct Graph::Impl {
  explicit Impl(ReplicaId self, GraphOptions opts) : self(self), options(opts) {}

  ReplicaId self;
  GraphOptions options;
  crdt::CausalContext ctx;
  std::unordered_map<NodeId, NodeRec> nodes;
  std::unordered_map<EdgeKey, EdgeRec> edges;
  std::size_t alive_count = 0;
  std::uint64_t epoch = 1;  // bumped by every commit and merge (invalidates transaction hints)
  std::unordered_map<std::string, crdt::SmallVec<NodeRec*, 1>> by_name;
  std::unordered_map<Symbol, std::unordered_set<NodeRec*>> by_type;

  // Kinematic tree bookkeeping.
  std::unordered_set<NodeRec*> claimants;            // records with a non-empty claim register
  std::unordered_map<NodeId, int> claim_parent_refs;  // node -> number of claims naming it
  bool rt_dirty = false;
  std::size_t rt_skips = 0;  // claims not applied as written in the last full derivation
  Dot rt_max_order;          // greatest winning claim dot applied so far

  // Local dot minting: counters are Lamport clocks (never below anything seen, up to
  // crdt::kClockCeiling), and never above crdt::kMaxCounter.
  std::uint64_t next_counter = 0;  // last counter handed out
  // Counters handed out as node ids by open transactions, ascending (minting only grows). A
  // commit publishes every unpublished counter below its own except these.
  std::vector<std::uint64_t> reserved;
  /// Removes `mine` (ascending) from `reserved`.
  void unreserve(const std::vector<std::uint64_t>& mine);
  std::size_t open_transactions = 0;  // transactions holding uncommitted changes

  // Output of local commits.
  GraphDelta out;
  std::unique_ptr<Transaction::Book> spare_book;  // the last transaction's, for the next one
  std::function<void(const GraphDelta&)> sink;
  CommitValidator validator;
  CommitValidator permission_check;
  std::function<bool(Symbol)> type_change_allowed;
  FenceProvider fence_of;
  Graph::OriginNamer origin_namer;
  std::vector<std::pair<Graph::ObserverId, MergeObserver>> merge_observers;
  Graph::ObserverId next_observer = 1;
  std::uint64_t fence(NodeId n) const { return fence_of ? fence_of(n) : 0; }
  /// An edge attribute carries the higher fence of its two ends.
  std::uint64_t edge_fence(const EdgeKey& k) const { return std::max(fence(k.from), fence(k.to)); }

  // Events. A deque: a callback may subscribe (the running callback's element stays put); one
  // unsubscribed during a dispatch is marked and erased once the dispatch ends.
  struct Subscriber {
    SubscriptionId id;
    ChangeCallback cb;
    bool removed = false;
  };
  std::deque<Subscriber> subscribers;
  SubscriptionId next_subscription = 1;
  ChangeTracker tracker;
  // The batch being built and dispatched, one per nesting level (a callback may commit), kept
  // with its changes' containers so that a batch like the last one allocates nothing.
  struct Dispatch {
    ChangeBatch batch;
    std::vector<NodeChange> spare_nodes;
    std::vector<EdgeChange> spare_edges;
    /// Empties the batch, keeping its changes (and their containers' capacity) as spares.
    void recycle();
    /// A change appended to the batch: recycled when there is one, its containers empty.
    NodeChange& add_node(NodeId id, ChangeKind kind, Symbol type);
    EdgeChange& add_edge(const EdgeKey& key, ChangeKind kind);
    /// Takes back the last change added (it turned out to change nothing).
    void drop_last_node();
    void drop_last_edge();
  };
  std::vector<std::unique_ptr<Dispatch>> dispatches;
  std::size_t dispatch_depth = 0;
  bool unsubscribed_in_dispatch = false;
  /// Writes the origin's name (origin_namer, else its id) into `out`.
  void name_origin(const ReplicaId& origin, std::string& out) const {
    if (origin_namer) origin_namer(origin, out);
    else origin.write_to(out);
  }

  // Scratch for commits and merges.
  std::vector<std::uint32_t> commit_order;
  std::vector<NodeId> pending_kills;
  std::vector<NodeId> gc_candidates;

  // ---- helpers (graph_records.cc) ----
  NodeRec* find_node(NodeId id) {
    auto it = nodes.find(id);
    return it == nodes.end() ? nullptr : &it->second;
  }
  const NodeRec* find_node(NodeId id) const {
    auto it = nodes.find(id);
    return it == nodes.end() ? nullptr : &it->second;
  }
  const NodeRec* visible_node(NodeId id) const {
    const NodeRec* r = find_node(id);
    return (r && r->alive) ? r : nullptr;
  }
  EdgeRec* find_edge(const EdgeKey& k) {
    auto it = edges.find(k);
    return it == edges.end() ? nullptr : &it->second;
  }
  const EdgeRec* find_edge(const EdgeKey& k) const {
    auto it = edges.find(k);
    return it == edges.end() ? nullptr : &it->second;
  }
  bool edge_visible(const EdgeRec& e) const;
  /// A node is dead when its creation dot was seen and its creation entry is gone: forever.
  bool is_dead(NodeId id) const {
    if (!ctx.contains(id.dot)) return false;
    const NodeRec* r = find_node(id);
    return r == nullptr || !r->alive;
  }
  NodeRec& node_record(NodeId id);  // finds or creates a (placeholder) record
  EdgeRec& edge_record(const EdgeKey& k);
  void erase_edge_record(EdgeRec* e);
  void erase_node_record_if_empty(NodeRec* r);
  void set_alive(NodeRec* r, bool alive, Symbol type, const std::string& name);
  void index_claim_entry(const RtClaim& c, int delta);
  bool insert_sample(NodeRec* r, const RtSample& s);
  // insert_sample(), and on success the sample goes out in the delta being built.
  bool record_sample(NodeRec* child, const RtSample& s);
  /// Removes every trace of a dead node: attributes, incident edges, claims, samples.
  void kill_record(NodeRec* r);
  void gc_candidates_sweep();

  // ---- events ----
  bool tracking() const { return options.always_track_changes || !subscribers.empty(); }
  void begin_tracking() {
    tracker.enabled = tracking();
    tracker.reset();
  }
  void touch_node(NodeRec* r) {
    if (tracker.enabled) tracker.touch_node(r->id, r->alive, r->type);
  }
  /// Call before changing the register `name` of r.
  void touch_attr(NodeRec* r, Symbol name) {
    if (tracker.enabled) save_attr(tracker.touch_node(r->id, r->alive, r->type)->attrs, name, r->attrs);
  }
  void touch_edge(const EdgeRec& e);
  /// Call before changing a symbolic edge's existence dots (a re-insert changes its version).
  void touch_edge_version(const EdgeRec& e);
  /// r's visible name may change; `before` is the name it had.
  void touch_renamed(NodeRec* r, std::string before);
  /// Call before changing the register `name` of an edge.
  void touch_edge_attr(const EdgeRec& e, Symbol name);
  /// What name_of() returns for a visible node.
  std::string visible_name(const NodeRec& r) const;
  void touch_incident_edges(NodeRec* r);
  /// Call before a change that may delete a visible node (with its incident edges) or a visible
  /// edge: saves what its deletion event carries (last name, attribute values). Once per batch.
  void save_last(NodeRec* r);
  void save_last(const EdgeRec& e);
  /// Saves r's RT view before the batch changes it (a no-op after the first call per batch).
  void touch_rt(const NodeRec* r) {
    if (tracker.enabled && !tracker.rt_saved(r->id)) tracker.save_rt(r->id, rt_view(*r));
  }
  RtView rt_view(const NodeRec& r) const;
  /// Builds and delivers the change batch; returns it (for tests).
  void finish_tracking(bool local, ReplicaId origin, const std::vector<std::pair<NodeRec*, NodeRec*>>* rt_before);
  std::vector<std::pair<Symbol, Value>> last_rt_values(const RtView& before, const std::vector<NodeChange>& nodes,
                                                       NodeId child, const NodeRec* now) const;
  void report_rt_attrs(Dispatch& d, std::size_t first_rt) const;

  // ---- kinematic tree (graph_rt.cc) ----
  void recompute_rt(std::vector<std::pair<NodeId, NodeId>>* changes);
  RtEdge current_rt(const NodeRec& r) const;
  /// After c's claim register changed: applies its winning claim directly when that equals a
  /// full derivation (the claim is the newest and nothing is skipped); otherwise marks dirty.
  void claim_updated(NodeRec* c);
  void link_rt(NodeRec* c, NodeRec* parent);
  /// Keeps `claimants` in step with c's claim register; a node without claims has no parent.
  void sync_claimant(NodeRec* c);
  bool would_cycle(const NodeRec* parent, const NodeRec* child) const;

  // ---- merging (graph_merge.cc) ----
  void merge_delta(const GraphDelta& d);
  void merge_state(const GraphDelta& s);
  /// The first phase of joining a state: removes every entry of ours whose dot `context` (the
  /// sender's) holds but `held` (the dots of the sender's entries, add_held()) does not.
  void remove_unheld(const crdt::CausalContext& context, const std::unordered_set<Dot>& held);
  /// Nodes whose ids `d` lists as removed dots go (at after_merge()).
  void kill_removed_ids(const GraphDelta& d);
  /// Adds what `d` adds and removes what it removes under its keys (phases shared by both).
  void merge_ops(const GraphDelta& d);
  void merge_register(AttrList& attrs, const GraphDelta& d, const GraphDelta::AttrOp& a);
  void after_merge(const GraphDelta& d, bool full_gc);

  // ---- local changes (graph_recording.cc) ----
  /// The next dot. @pre can_mint(1).
  Dot mint();
  /// True if `n` more dots fit below crdt::kMaxCounter.
  bool can_mint(std::uint64_t n) const;
  /// Publishes every own counter in [1, next_counter] not yet in the context and not reserved
  /// by another open transaction: into the context and the outgoing delta's context.
  void publish_own_dots(CommitInfo& info);
  GraphDelta::NodeOp& out_node(NodeId id, int section);
  GraphDelta::EdgeOp& out_edge(const EdgeKey& key);
  void local_write_attr(NodeRec* r, Symbol name, Value v);
  void local_remove_attr(NodeRec* r, Symbol name);
  void local_create_node(NodeId id, Symbol type, const std::string& name,
                         const std::vector<std::pair<Symbol, Value>>& attrs);
  void local_delete_node(NodeRec* r);
  void local_insert_edge(const EdgeKey& key, const std::vector<std::pair<Symbol, Value>>& attrs);
  void local_delete_edge(EdgeRec* e);
  void local_write_edge_attr(EdgeRec* e, Symbol name, const Value* v);
  void local_set_rt(NodeRec* parent, NodeRec* child, const Pose& pose, std::int64_t stamp);
  void local_remove_rt(NodeRec* child);
  void record_attr_removals(std::vector<GraphDelta::AttrOp>& ops, AttrList& attrs);
  void record_edge_removal(EdgeRec& e);
};

/// The library's own free functions that work on a graph's records (state_parts.h).
struct GraphAccess {
  static Graph::Impl& of(Graph& g) { return *g.impl_; }
  static const Graph::Impl& of(const Graph& g) { return *g.impl_; }
};

}  // namespace quiver::graph
