#pragma once
/// @file
/// The symbolic part of a world, as missions and planners see it (AGM's `AGMGraph`): typed
/// nodes and labelled edges, no attributes, no poses. Compact and cheap to copy, so that a
/// planner can hold many states; compared and hashed exactly (the same nodes, types and edges).
///
/// Nodes are dense indices (NodeIx) that stay valid across the states of one problem: a node a
/// rule creates gets the next index, a deleted node keeps its index with no type (absent).
/// Types and labels are indices into a Vocabulary shared by every state of the problem.

#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "quiver/agents/rules/grammar/grammar.h"
#include "quiver/graph/graph.h"

namespace quiver::agents::inline rules::symbolic {

using NodeIx = std::uint32_t;
using TypeIx = std::uint16_t;
using LabelIx = std::uint32_t;
inline constexpr NodeIx kNoNode = std::numeric_limits<NodeIx>::max();
inline constexpr TypeIx kAbsent = std::numeric_limits<TypeIx>::max();

/// Type and label names of a problem, and type inheritance (from a grammar's TypeSystem).
class Vocabulary {
 public:
  Vocabulary() = default;
  explicit Vocabulary(TypeSystem types) : types_(std::move(types)) {}
  /// The index of a type name, interning it.
  TypeIx type(std::string_view name);
  /// The index of a label, interning it.
  LabelIx label(std::string_view name);
  /// The index of a type or label name, if interned.
  std::optional<TypeIx> find_type(std::string_view name) const;
  std::optional<LabelIx> find_label(std::string_view name) const;
  const std::string& type_name(TypeIx t) const { return type_names_[t]; }
  const std::string& label_name(LabelIx l) const { return label_names_[l]; }
  std::size_t type_count() const { return type_names_.size(); }
  std::size_t label_count() const { return label_names_.size(); }
  /// True if `t` is `base` or inherits from it (the grammar's inheritance; cached).
  bool is_a(TypeIx t, TypeIx base) const;
  const TypeSystem& types() const { return types_; }

 private:
  TypeSystem types_;
  std::vector<std::string> type_names_, label_names_;
  std::unordered_map<std::string, TypeIx> type_ix_;
  std::unordered_map<std::string, LabelIx> label_ix_;
  mutable std::vector<std::vector<std::int8_t>> is_a_;  // [t][base]: -1 unknown, 0, 1
};

struct Edge {
  NodeIx from = 0;
  LabelIx label = 0;
  NodeIx to = 0;
  friend bool operator==(const Edge&, const Edge&) = default;
  friend auto operator<=>(const Edge&, const Edge&) = default;  // (from, label, to)
};

/// One symbolic state. Edges are kept sorted by (from, label, to) and, for lookups by target,
/// by (to, label, from) in `in`.
class State {
 public:
  std::size_t size() const { return types_.size(); }
  bool alive(NodeIx n) const { return n < types_.size() && types_[n] != kAbsent; }
  TypeIx type(NodeIx n) const { return types_[n]; }
  std::size_t alive_count() const { return alive_; }
  const std::vector<Edge>& edges() const { return out_; }
  bool has_edge(NodeIx from, NodeIx to, LabelIx label) const;
  /// Edges from `from` with `label` (a contiguous range of edges()).
  std::pair<const Edge*, const Edge*> out(NodeIx from, LabelIx label) const;
  /// Edges into `to` with `label` (reversed: Edge::from is the target, Edge::to the source).
  std::pair<const Edge*, const Edge*> in(NodeIx to, LabelIx label) const;

  /// Adds a node of type `t`. @returns its index (the next one).
  NodeIx add_node(TypeIx t);
  /// Deletes a node and its edges.
  void delete_node(NodeIx n);
  void retype(NodeIx n, TypeIx t) { types_[n] = t; hashed_ = false; }
  /// Adds an edge (nothing if present or an end is absent).
  void add_edge(NodeIx from, NodeIx to, LabelIx label);
  void remove_edge(NodeIx from, NodeIx to, LabelIx label);

  std::uint64_t hash() const;
  friend bool operator==(const State& a, const State& b) {
    return a.types_ == b.types_ && a.out_ == b.out_;
  }

 private:
  std::vector<TypeIx> types_;
  std::vector<Edge> out_, in_;
  std::size_t alive_ = 0;
  mutable std::uint64_t hash_ = 0;
  mutable bool hashed_ = false;
};

/// A state read from a graph replica, with the way back to the graph's nodes.
struct World {
  Vocabulary vocabulary;
  State state;
  std::vector<graph::NodeId> ids;     ///< per NodeIx of the state read
  std::vector<std::string> names;     ///< node names, per NodeIx
  std::vector<std::string> agm_ids;   ///< AGM symbol ids (`agm_id` attribute), "" if none
  std::int64_t max_agm_id = -1;       ///< the largest numeric AGM id (-1: none)
  std::size_t initial = 0;            ///< nodes read from the graph (later ones: created by plans)
  /// The node with AGM id (or, failing that, name) `key`.
  NodeIx find(std::string_view key) const;
  /// AGM id if any, else the name: how plans and reports name a node. A node a plan creates is
  /// the next AGM id above the world's largest (as AGM numbers them), or `new_<index>`.
  std::string label(NodeIx n) const;
};

/// Reads the symbolic part of `g`: every node (type, name, `agm_id`), every symbolic edge and
/// every RT edge (label "RT", parent -> child), in a deterministic order (by name).
/// `types` gives inheritance (a grammar's); types and labels are interned in the result's
/// vocabulary. Nodes for which `hide` returns true are left out, with their edges.
World read_world(const graph::Graph& g, TypeSystem types = {},
                 const std::function<bool(graph::NodeId)>& hide = {});

}  // namespace quiver::agents::inline rules::symbolic
