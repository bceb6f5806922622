#pragma once
/// @file
/// A bounded, in-memory history of frames that can rebuild the state after any of them (a
/// viewer's timeline, a renderer of a recording).
///
/// Frames are numbered from 0 in arrival order; numbers stay valid while the history runs. When
/// the frames kept pass `max_bytes` (their encoded size) or `max_frames`, the oldest are folded
/// into a base state, so the earliest frame still listed moves on but every listed one can still be
/// rebuilt.

#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "quiver/agents/recording/frame.h"
#include "quiver/graph/graph.h"
#include "quiver/result.h"

namespace quiver::agents::recording {

class History {
 public:
  explicit History(std::uint64_t max_bytes = 64ull << 20, std::uint64_t max_frames = UINT64_MAX);
  ~History();
  History(History&&) noexcept;
  History& operator=(History&&) noexcept;

  /// Appends a frame (numbered end() - 1 afterwards).
  void add(Frame f);
  /// The first frame still listed, and one past the last.
  std::uint64_t begin() const { return first_; }
  std::uint64_t end() const { return first_ + kept_.size(); }
  bool empty() const { return kept_.empty(); }
  std::uint64_t bytes() const { return bytes_; }
  /// Frames folded into the base state so far.
  std::uint64_t folded() const { return first_; }

  /// Frame `i` (decoded again from its stored bytes). kNotFound when i is not listed.
  Result<Frame> frame(std::uint64_t i) const;
  /// Time and origin of frame i without decoding its delta.
  std::int64_t time_of(std::uint64_t i) const;
  const std::string& origin_of(std::uint64_t i) const;

  /// A graph holding the state after frame `i` (the base state, then frames begin()..i), and,
  /// if `changes` is given, what frame i changed. kNotFound when i is not listed.
  Result<std::unique_ptr<graph::Graph>> state_after(std::uint64_t i,
                                                    graph::ChangeBatch* changes = nullptr) const;
  /// Rebuilds the states after frames begin()..last in order and calls `fn(i, graph after i,
  /// what frame i changed)` for each i >= `from`. kNotFound when `last` is not listed.
  using ReplayFn =
      std::function<void(std::uint64_t, const graph::Graph&, const graph::ChangeBatch&)>;
  Status replay(std::uint64_t from, std::uint64_t last, const ReplayFn& fn) const;

 private:
  // replay() into `g` (empty), which holds the state after `last` when it returns.
  Status replay_into(graph::Graph& g, std::uint64_t from, std::uint64_t last,
                     const ReplayFn& fn) const;
  struct Kept {
    std::int64_t t_ns;
    std::string origin;
    std::vector<std::uint8_t> delta;  // graph codec
  };
  std::uint64_t max_bytes_;
  std::uint64_t max_frames_;
  std::uint64_t first_ = 0;
  std::uint64_t bytes_ = 0;
  std::deque<Kept> kept_;
  std::unique_ptr<graph::Graph> base_;
};

/// The replica id the graphs rebuilt from recordings use as their own (they never commit).
graph::ReplicaId replay_replica_id();

}  // namespace quiver::agents::recording
