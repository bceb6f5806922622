#pragma once
/// @file
/// Transforms between any two frames of the graph's kinematic (RT) tree, now or at a past time.
///
/// Every graph node is a frame. An RT edge P -> C holds X_PC, the pose of frame C in frame P, and
/// a bounded history of timestamped samples (graph::kRtHistoryDepth, replicated: every replica
/// keeps the same samples). A FrameTree mirrors the tree of one graph on the graph's owner thread
/// and publishes it to FrameReaders on any thread:
///
///  - current-time lookups are O(1): each frame caches X_RF, its pose in the root frame R of its
///    tree, and X_AB = X_RA⁻¹·X_RB. One cache entry per frame, none per pair. When an RT edge
///    changes (a local commit or a merge), only the cache entries of the subtree under it are
///    recomputed, and each carries a version that is bumped then;
///  - timed lookups walk from A and B up to their lowest common ancestor, interpolating each edge
///    at time t between its two bracketing samples (linear translation, slerp rotation). Only
///    samples taken under the edge's current parent are used (the same "epoch" of the
///    replicated move), so an interpolation never crosses a change of parent;
///  - readers never take a lock, never write memory another thread reads on the hot path and
///    never wait for the owner: the owner writes each update twice, into two copies of the table
///    (a sequence-count latch), so a reader always has a consistent copy to read.
///
/// Failures are values (quiver::Result) worded like tf2's: an unknown frame (kNotFound), frames
/// in separate trees (kNotConnected), a time outside the stored history (kExtrapolation, naming the
/// requested and the available times) and invalid arguments (kInvalidArgument).
///
/// Names: X_AB is the pose of frame B in frame A (it maps p_BoQ_B to p_AoQ_A); lookup(A, B)
/// returns X_AB, as tf2's lookupTransform(target = A, source = B).

#include <Eigen/Geometry>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "quiver/graph/graph.h"
#include "quiver/base/result.h"

namespace quiver::kinematics {

namespace internal {
struct Core;
}  // namespace internal

/// Replicated time of RT samples: the graph's int64 stamps (nanoseconds by convention).
using Time = std::int64_t;

/// A handle to a frame: a dense slot and the slot's generation. Cheap to copy; it goes stale (and
/// lookups with it fail with kNotFound) when its node is deleted.
struct Frame {
  std::uint32_t slot = 0;
  std::uint32_t generation = 0;  ///< 0: the null handle

  bool is_null() const { return generation == 0; }
  friend bool operator==(const Frame&, const Frame&) = default;
};

/// Names a frame in a lookup: by node name, by node id or by handle.
class FrameRef {
 public:
  FrameRef(std::string_view name) : kind_(Kind::kName), name_(name) {}    // NOLINT
  FrameRef(const char* name) : kind_(Kind::kName), name_(name) {}         // NOLINT
  FrameRef(const std::string& name) : kind_(Kind::kName), name_(name) {}  // NOLINT
  FrameRef(graph::NodeId id) : kind_(Kind::kId), id_(id) {}               // NOLINT
  FrameRef(Frame f) : kind_(Kind::kHandle), frame_(f) {}                  // NOLINT

  enum class Kind : std::uint8_t { kName, kId, kHandle };
  Kind kind() const { return kind_; }
  std::string_view name() const { return name_; }
  graph::NodeId id() const { return id_; }
  Frame frame() const { return frame_; }
  /// For error messages: "\"gripper\"", "node 0000000000000001.1:7", "frame #3/1".
  std::string describe() const;

 private:
  Kind kind_;
  std::string_view name_;
  graph::NodeId id_;
  Frame frame_;
};

/// Lookups against the published frame table. One FrameReader per thread: a reader is not itself
/// thread-safe, but any number of readers on any threads run concurrently with each other and
/// with the owner thread's updates, without locks.
///
/// A reader announces, at each call, which version of the replaced objects it may still see; a
/// reader that will stay idle for long should be destroyed (or call `idle()`) so the owner can
/// free what it replaced. Readers stay valid after their FrameTree is destroyed (they keep
/// answering from its last state).
class FrameReader {
 public:
  FrameReader(FrameReader&&) noexcept;
  FrameReader& operator=(FrameReader&&) noexcept;
  FrameReader(const FrameReader&) = delete;
  FrameReader& operator=(const FrameReader&) = delete;
  ~FrameReader();

  /// Resolves a frame to a handle.
  /// @returns kNotFound for an unknown name, id or stale handle; kInvalidArgument for "".
  Result<Frame> frame(FrameRef f);
  /// The node a frame stands for.
  Result<graph::NodeId> node(FrameRef f);
  /// The name of a frame (its node's effective name).
  Result<std::string> name(FrameRef f);

  /// X_AB now: the pose of frame B in frame A (from the current poses of every edge). O(1).
  /// @returns kNotFound, kInvalidArgument or kNotConnected (A and B in separate trees).
  Result<Eigen::Isometry3d> lookup(FrameRef A, FrameRef B);
  /// p_AoBo_A: where B's origin is in A (lookup(A, B)'s translation); DSR's
  /// get_translation_vector(A, B). @returns lookup()'s errors.
  Result<Eigen::Vector3d> translation(FrameRef A, FrameRef B) {
    auto X_AB = lookup(A, B);
    if (!X_AB.ok()) return X_AB.error();
    return Eigen::Vector3d(X_AB->translation());
  }
  /// R_AB: B's orientation in A (lookup(A, B)'s rotation); DSR's get_rotation_matrix(A, B).
  Result<Eigen::Matrix3d> rotation(FrameRef A, FrameRef B) {
    auto X_AB = lookup(A, B);
    if (!X_AB.ok()) return X_AB.error();
    return Eigen::Matrix3d(X_AB->linear());
  }
  /// X_AB at replicated time `t`, interpolated on every edge of the path between A and B.
  /// @returns as lookup(), plus kExtrapolation when `t` is before the earliest or after the
  /// latest sample of an edge on the path (the message names the edge and both times).
  Result<Eigen::Isometry3d> lookup_at(FrameRef A, FrameRef B, Time t);
  /// p_AoQ_A, the point Q given in frame B (p_BoQ_B) expressed in frame A, now or at `t`.
  Result<Eigen::Vector3d> transform_point(FrameRef A, FrameRef B, const Eigen::Vector3d& p_BoQ_B,
                                          std::optional<Time> t = std::nullopt);
  /// X_AC from X_BC: a pose given in frame B expressed in frame A, now or at `t`.
  Result<Eigen::Isometry3d> transform_pose(FrameRef A, FrameRef B, const Eigen::Isometry3d& X_BC,
                                           std::optional<Time> t = std::nullopt);
  /// X_RF and the root R of F's tree (R = F for a frame without RT parent).
  Result<std::pair<Frame, Eigen::Isometry3d>> root_pose(FrameRef F);
  /// A counter bumped whenever X_RF (or F's root) changes: equal versions, equal pose.
  Result<std::uint64_t> pose_version(FrameRef F);
  /// The time range [earliest, latest] that lookup_at() can answer on F's edge to its parent.
  /// @returns kNotFound, or kNotConnected if F has no parent.
  Result<std::pair<Time, Time>> edge_time_range(FrameRef F);

  /// How many batches the owner has published (a change counter for the whole table).
  std::uint64_t version() const;
  /// Marks this reader as holding nothing until its next call (lets the owner free memory).
  void idle();

 private:
  friend class FrameTree;
  FrameReader(std::shared_ptr<internal::Core> core, bool registered);
  void enter();
  /// enter(), then resolves `f` and runs `read(copy, slot, out)` under the latch; an error named
  /// after the calling method `fn` if `f` does not resolve or `read` fails.
  template <class T, class Read>
  Result<T> read_frame(const char* fn, const FrameRef& f, Read&& read);

  std::shared_ptr<internal::Core> core_;
  int reader_index_ = -1;  ///< slot in the reader registry; -1 for the owner's own reader
  std::uint64_t announced_ = 0;
};

struct FrameTreeOptions {
  /// Subscribe to the graph and follow its changes. If false, call sync() by hand.
  bool follow = true;
  /// After every batch, compare this many frames (round robin) with the graph and repair any
  /// difference (see audit()). Off by default: the graph announces every change it makes.
  std::size_t audit_per_batch = 0;
};

/// What one update of the FrameTree changed, for owner-thread listeners (e.g. the collision
/// scene): frames created, frames whose X_RF or root changed, nodes removed.
struct FrameUpdate {
  const graph::ChangeBatch* batch = nullptr;  ///< the graph batch; null after sync()
  std::span<const Frame> moved;               ///< X_RF or root changed (created frames included)
  std::span<const graph::NodeId> removed;     ///< nodes whose frames were removed
  bool resynced = false;                      ///< rebuilt from scratch: every frame may have moved
};

/// Mirrors the kinematic tree of one graph. Lives on the graph's owner thread: construct it, let
/// it follow the graph's change events, and hand `reader()`s to other threads. Its own lookup
/// methods are for the owner thread.
class FrameTree {
 public:
  /// Builds the table from `g` and (by default) subscribes to its changes. `g` must outlive the
  /// tree, or the tree must be destroyed first.
  explicit FrameTree(graph::Graph& g, FrameTreeOptions options = {});
  /// A tree that does not follow `g` (e.g. to inspect a graph one may not subscribe to): it
  /// reflects `g` as it is now, and again after each sync().
  explicit FrameTree(const graph::Graph& g);
  ~FrameTree();
  FrameTree(const FrameTree&) = delete;
  FrameTree& operator=(const FrameTree&) = delete;

  /// A reader for another thread (or this one).
  /// @throws std::length_error when 64 readers are already registered.
  FrameReader reader();

  // ---- Owner-thread lookups (same contracts as FrameReader's) ----
  Result<Frame> frame(FrameRef f) { return self_.frame(f); }
  Result<Eigen::Isometry3d> lookup(FrameRef A, FrameRef B) { return self_.lookup(A, B); }
  Result<Eigen::Vector3d> translation(FrameRef A, FrameRef B) { return self_.translation(A, B); }
  Result<Eigen::Matrix3d> rotation(FrameRef A, FrameRef B) { return self_.rotation(A, B); }
  Result<Eigen::Isometry3d> lookup_at(FrameRef A, FrameRef B, Time t) {
    return self_.lookup_at(A, B, t);
  }
  Result<Eigen::Vector3d> transform_point(FrameRef A, FrameRef B, const Eigen::Vector3d& p_BoQ_B,
                                          std::optional<Time> t = std::nullopt) {
    return self_.transform_point(A, B, p_BoQ_B, t);
  }
  Result<Eigen::Isometry3d> transform_pose(FrameRef A, FrameRef B, const Eigen::Isometry3d& X_BC,
                                           std::optional<Time> t = std::nullopt) {
    return self_.transform_pose(A, B, X_BC, t);
  }
  Result<std::pair<Frame, Eigen::Isometry3d>> root_pose(FrameRef F) { return self_.root_pose(F); }
  Result<std::pair<Time, Time>> edge_time_range(FrameRef F) { return self_.edge_time_range(F); }

  // ---- Owner-side access for modules built on the tree (collision scene) ----
  /// The frame of a node (null handle if the node is not visible).
  Frame frame_of(graph::NodeId id) const;
  /// X_RF for a live frame (the owner's copy; no latch).
  std::optional<Eigen::Isometry3d> root_pose_of(Frame f) const;
  /// The root frame of a live frame's tree.
  Frame root_of(Frame f) const;
  graph::NodeId node_of(Frame f) const;
  /// Called on the owner thread after every update, once the new state is published.
  using Listener = std::function<void(const FrameUpdate&)>;
  std::uint64_t add_listener(Listener l);
  void remove_listener(std::uint64_t id);

  /// Rebuilds everything from the graph (e.g. with follow = false, or after a graph change that
  /// raised no event).
  void sync();
  /// Compares up to `frames` frames (round robin) with the graph and repairs those that differ;
  /// returns how many did (also counted in Stats::repairs). A followed tree needs none: the
  /// graph reports every change as an event, and the tests hold it to that with the audit off.
  /// It stays as a cheap check for an application that wants one (see
  /// FrameTreeOptions::audit_per_batch); sync() rebuilds everything at once.
  std::size_t audit(std::size_t frames);
  /// Compares the table with a fresh derivation from the graph; one message per difference.
  std::vector<std::string> check_against_graph() const;

  struct Stats {
    std::size_t frames = 0;
    std::uint64_t publishes = 0;
    std::uint64_t pose_recomputes = 0;  ///< X_RF cache entries recomputed, in total
    std::uint64_t resyncs = 0;
    std::uint64_t repairs = 0;        ///< frames audit() found different from the graph
    std::size_t retired_pending = 0;  ///< replaced objects not yet freed
  };
  Stats stats() const;
  const graph::Graph& graph() const { return *g_; }

  struct Owner;  ///< implementation detail (the owner's copy of the tree)

 private:
  void on_batch(const graph::ChangeBatch& b);
  void publish(FrameUpdate& u);

  const graph::Graph* g_;
  graph::Graph* followed_ = nullptr;
  std::shared_ptr<internal::Core> core_;
  std::unique_ptr<Owner> own_;
  FrameReader self_;
  std::optional<graph::Graph::SubscriptionId> sub_;
};

}  // namespace quiver::kinematics
