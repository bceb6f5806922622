#pragma once
// Private: the owner's copy of the frame tree (FrameTree::Owner): its frames with their samples
// and root-pose cache, the key tables' bookkeeping, listeners, and the updater's buffers.

#include <algorithm>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <utility>
#include <vector>

#include "frame_store.h"
#include "pose_math.h"
#include "quiver/kinematics/frames.h"

namespace quiver::kinematics {
namespace internal {

struct Sample {
  Time stamp;
  QP X;
};

/// Exact equality, number by number (==, as std::equal: -0 equals +0).
inline bool same_values(const QP& a, const QP& b) {
  return std::equal(a.q, a.q + 4, b.q) && std::equal(a.p, a.p + 3, b.p);
}
inline bool same_values(const Sample& a, const Sample& b) {
  return a.stamp == b.stamp && same_values(a.X, b.X);
}

/// The owner's copy of one frame.
struct Node {
  graph::NodeId id;
  bool live = false;
  std::uint32_t generation = 1;
  std::string name;  // effective name
  std::int32_t parent = kNone;
  std::vector<std::int32_t> children;
  QP X_PN;
  Time stamp = 0;
  std::vector<Sample> samples;  // current epoch, ascending, distinct stamps (published if >= 2)
  // Root-pose cache.
  double R_RN[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  double p_RN[3] = {0, 0, 0};
  std::int32_t root = kNone;
  std::uint32_t depth = 0;
  std::uint64_t version = 0;
  // Bookkeeping.
  bool world_dirty = false;
  bool touched = false;  // to publish
  bool hist_dirty = false;
  const std::string* pub_name = nullptr;
  HistoryBlock* pub_hist[2] = {nullptr, nullptr};
};

struct TableOp {
  bool insert;
  std::uint64_t hash;
  std::uint32_t slot;
};

/// The owner's bookkeeping of one published key table (both copies are identical).
struct TableState {
  std::uint32_t capacity = 0;
  std::uint32_t used = 0;  // non-empty entries (live and tombstones)
  std::uint32_t live = 0;
  std::vector<TableOp> ops;
  bool rebuild = true;
};

/// Base of a stored name ("mug" for "mug~0000...").
inline std::string base_name(const std::string& effective) {
  auto t = effective.find('~');
  return t == std::string::npos ? effective : effective.substr(0, t);
}

}  // namespace internal

struct FrameTree::Owner {
  std::vector<internal::Node> nodes;
  std::vector<std::int32_t> free_slots;
  std::unordered_map<graph::NodeId, std::int32_t> by_id;
  std::unordered_map<std::string, std::int32_t> by_name;
  internal::TableState names, ids;
  std::vector<std::int32_t> touched;  // slots to publish
  std::vector<std::int32_t> world_dirty_roots;
  std::vector<Frame> moved;
  std::vector<graph::NodeId> removed;
  std::vector<std::pair<std::uint64_t, Listener>> listeners;
  std::vector<std::pair<std::uint64_t, Listener>> notifying;  // notify()'s snapshot buffer
  std::uint64_t next_listener = 1;
  std::uint64_t audit_cursor = 0;
  std::size_t audit_per_batch = 0;
  Stats stats;
  // The Updater's working buffers, kept between batches (cleared, not freed).
  std::vector<graph::NodeId> rt_dirty;
  std::unordered_set<graph::NodeId> rt_seen;
  std::vector<std::int32_t> marked, stack, path;
  std::vector<internal::Sample> samples;

  void touch(std::int32_t s) {
    if (!nodes[s].touched) {
      nodes[s].touched = true;
      touched.push_back(s);
    }
  }

  /// Calls every listener. A callback may add or remove listeners, or cause a nested update:
  /// the listeners registered now are called, from a snapshot (in a reused buffer; a nested call
  /// finds it taken and makes its own).
  void notify(const FrameUpdate& u) {
    if (listeners.empty()) return;
    std::vector<std::pair<std::uint64_t, Listener>> snapshot;
    snapshot.swap(notifying);
    snapshot.assign(listeners.begin(), listeners.end());
    for (auto& [id, l] : snapshot) l(u);
    snapshot.clear();
    notifying.swap(snapshot);
  }
};

}  // namespace quiver::kinematics
