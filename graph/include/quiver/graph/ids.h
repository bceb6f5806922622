#pragma once
/// @file
/// Identifiers of the world graph and the payloads of kinematic (RT) edges.
///
/// Threading: plain values with no shared state; every function here is thread-safe on
/// distinct objects (and on shared ones that nobody writes).

#include <array>
#include <compare>
#include <cstdint>
#include <functional>
#include <string>

#include "quiver/crdt/dot.h"
#include "quiver/graph/symbol.h"

namespace quiver::graph {

using crdt::Dot;
using crdt::ReplicaId;

/// A node's id is the dot of its creation: unique without any central id server.
struct NodeId {
  Dot dot;

  /// @returns true for the null id (a null dot: counter 0), which names no node.
  bool is_null() const { return dot.is_null(); }
  friend auto operator<=>(const NodeId&, const NodeId&) = default;
  friend bool operator==(const NodeId&, const NodeId&) = default;
  /// @returns the dot as text: "00000000000000ab.3:42" (agent in hex, incarnation, counter).
  std::string to_string() const { return dot.to_string(); }
};

/// An edge is identified by its endpoints and its type: several types may link one pair.
struct EdgeKey {
  NodeId from;
  NodeId to;
  Symbol type;

  friend bool operator==(const EdgeKey&, const EdgeKey&) = default;
  /// @returns "<from> -[<type>]-> <to>", with ids as NodeId::to_string() writes them.
  std::string to_string() const;
};

/// Deterministic order of edge keys (types by text).
/// @returns true if `a` sorts before `b`: by `from`, then `to` (NodeId order), then type text.
bool canonical_less(const EdgeKey& a, const EdgeKey& b);

/// A rigid transform X_PC: the pose of a child frame C in its parent frame P, as a translation
/// p_PoCo_P and a unit quaternion R_PC = (w, x, y, z).
struct Pose {
  std::array<double, 3> translation{0.0, 0.0, 0.0};
  std::array<double, 4> rotation{1.0, 0.0, 0.0, 0.0};

  friend bool operator==(const Pose&, const Pose&) = default;
  /// @returns the identity transform (zero translation, rotation (1, 0, 0, 0)).
  static Pose identity() { return Pose{}; }
};

/// One claim "child C hangs under `parent`", written when C is (re)parented. Concurrent claims
/// are ordered by their dots (Lamport order), as in the replicated-tree move operation; a claim
/// that would close a cycle falls back to the parent C had when the claim was made.
struct RtClaim {
  NodeId parent;            ///< Null: C is detached (a root).
  Pose pose;                ///< X_PC at the time of the move.
  std::int64_t stamp = 0;   ///< Replicated time of `pose` (e.g. nanoseconds).
  NodeId fallback_parent;   ///< C's parent when the claim was made (null if none).
  Pose fallback_pose;       ///< and its pose then,
  std::int64_t fallback_stamp = 0;  ///< taken at this time,
  Dot fallback_epoch;       ///< under the claim that had set `fallback_parent`.

  friend bool operator==(const RtClaim&, const RtClaim&) = default;
};

/// One timestamped pose of an RT edge. `epoch` is the dot of the claim (move) it belongs to,
/// so interpolation never mixes poses taken under different parents.
struct RtSample {
  std::int64_t stamp = 0;
  Dot dot;    ///< Identity of the sample (and tie-break for equal stamps).
  Dot epoch;
  Pose pose;

  friend bool operator==(const RtSample&, const RtSample&) = default;
};

/// Samples ordered by (stamp, dot).
/// @returns true if `a` sorts before `b`: by stamp, then by dot in Lamport order.
inline bool sample_less(const RtSample& a, const RtSample& b) {
  if (a.stamp != b.stamp) return a.stamp < b.stamp;
  return crdt::lamport_less(a.dot, b.dot);
}

/// How many samples each RT edge keeps (the newest by stamp). Part of the replicated semantics:
/// every replica must use the same value.
inline constexpr std::size_t kRtHistoryDepth = 32;

}  // namespace quiver::graph

template <>
struct std::hash<quiver::graph::NodeId> {
  /// @returns hash_value() of the id's dot (stable across processes).
  std::size_t operator()(const quiver::graph::NodeId& n) const noexcept { return hash_value(n.dot); }
};
template <>
struct std::hash<quiver::graph::EdgeKey> {
  /// @returns a hash of both endpoints and the type's stable_hash() (stable across processes).
  std::size_t operator()(const quiver::graph::EdgeKey& k) const noexcept {
    return quiver::hash_combine(quiver::hash_combine(hash_value(k.from.dot), hash_value(k.to.dot)),
                                k.type.stable_hash());
  }
};
