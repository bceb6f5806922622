#pragma once
/// @file
/// GraphDelta: a fragment of the graph CRDT's state, used for deltas (a transaction's changes),
/// delta intervals (several deltas of one origin, concatenated) and state transfers (a full state
/// or a context diff).
///
/// Layout: flat arrays with index ranges, so that building and decoding allocate nothing once
/// warm. Every dot a delta removes is listed under the key it was removed from ("attributed"),
/// which lets a receiver join a delta in time proportional to the delta, not to its own state.
///
/// Threading: a plain value; no shared state.

#include <cstdint>
#include <string>
#include <vector>

#include "quiver/crdt/causal_context.h"
#include "quiver/crdt/dot_store.h"
#include "quiver/graph/ids.h"
#include "quiver/graph/value.h"

namespace quiver::graph {

struct GraphDelta {
  enum class Kind : std::uint8_t {
    kDelta = 1,  ///< Attributed changes; `context` holds the dot ranges the origin minted.
    kState = 2,  ///< A full state or context diff; `context` is the sender's whole context.
  };
  struct Span {
    std::uint32_t begin = 0;
    std::uint32_t end = 0;
    /// @returns the number of indices in [begin, end).
    /// @pre begin <= end.
    std::uint32_t size() const { return end - begin; }
    /// @returns true if the span holds no index.
    bool empty() const { return begin == end; }
  };
  /// Changes of one attribute register.
  struct AttrOp {
    Symbol name;
    Span removed;  ///< into `removed`
    Span added;    ///< into `values`
  };
  /// Changes under one node key.
  struct NodeOp {
    NodeId id;
    bool has_header = false;  ///< Creation entry (dot = id) with type and name.
    bool removed = false;     ///< The creation dot is removed: the node is deleted.
    Symbol type;
    std::string name;
    Span attrs;          ///< into `attrs`
    Span claim_removed;  ///< into `removed`
    Span claim_added;    ///< into `claims`
    Span samples;        ///< into `samples`
  };
  /// Changes under one edge key.
  struct EdgeOp {
    EdgeKey key;
    Span removed;  ///< existence dots removed, into `removed`
    Span added;    ///< existence dots added, into `added`
    Span attrs;    ///< into `attrs`
  };

  Kind kind = Kind::kDelta;
  ReplicaId origin;
  /// The protocol's sequence numbers this payload carries (kDelta: the origin's delta interval
  /// [seq_lo, seq_hi]; 0: unbound). Binding them into the payload means a payload cannot be
  /// replayed under another interval.
  std::uint64_t seq_lo = 0;
  std::uint64_t seq_hi = 0;
  crdt::CausalContext context;
  std::vector<NodeOp> nodes;
  std::vector<EdgeOp> edges;
  std::vector<AttrOp> attrs;
  std::vector<Dot> removed;
  std::vector<Dot> added;
  std::vector<crdt::Entry<Value>> values;
  std::vector<crdt::Entry<RtClaim>> claims;
  std::vector<RtSample> samples;
  /// kState only: dots of entries the sender holds that the receiver's context already had.
  std::vector<Dot> keep;
  /// Optional claim of the grammar rule this delta applies and the node each variable matched,
  /// so that receivers can verify it without searching (empty rule: no claim).
  std::string rule;
  std::vector<std::pair<std::string, NodeId>> binding;

  /// Resets every field to its default (kind kDelta, null origin, no claim), keeping capacity.
  void clear();
  /// Empties the ops and the arrays they index, and the keep list (a state sent in parts: the
  /// next part reuses them); the header, context, rule and binding stay.
  void clear_ops();
  /// @returns true if the fragment carries no node op, no edge op and an empty context.
  bool empty() const { return nodes.empty() && edges.empty() && context.empty(); }
  /// Number of entry-level changes (for statistics).
  /// @returns the count of entries added and removed: values, existence dots, headers, node
  ///          removals, claims and samples.
  std::size_t change_count() const;
  /// Appends `other` (a later delta of the same origin) to this one: sequential application of
  /// the result equals applying both in order. Contexts are joined; the rule claim is dropped
  /// (an interval applies several rules).
  /// @pre Both are kDelta fragments of one origin, `other` later; their spans index their own
  ///      arrays (as built by a Graph or decode()). `other` is not `*this`.
  void append(const GraphDelta& other);
  /// Calls f(dot) for every dot this fragment adds or removes (its context beyond `context`).
  /// Includes the ids of nodes it creates or deletes. @pre `f` does not modify this fragment.
  template <class F>
  void for_each_mentioned_dot(F&& f) const {
    for (const Dot& d : removed) f(d);
    for (const Dot& d : added) f(d);
    for (const auto& e : values) f(e.dot);
    for (const auto& e : claims) f(e.dot);
    for (const auto& s : samples) f(s.dot);
    for (const auto& n : nodes)
      if (n.has_header || n.removed) f(n.id.dot);
  }
};

}  // namespace quiver::graph
