#pragma once
/// @file
/// Replays a recording's frames in order into one graph, a frame at a time, telling what each
/// frame changed. One pass over n frames costs n merges, where History::state_after() rebuilds
/// from the start for each frame: the timeline and `quiver render --at N` read states this way.

#include <cstddef>
#include <span>

#include "quiver/agents/recording/frame.h"
#include "quiver/graph/graph.h"

namespace quiver::agents::render {

class Replay {
 public:
  /// @param frames borrowed: they must outlive the Replay.
  explicit Replay(std::span<const recording::Frame> frames);
  ~Replay();
  Replay(const Replay&) = delete;
  Replay& operator=(const Replay&) = delete;

  std::size_t size() const { return frames_.size(); }
  /// The frame step() merges next (size() when done).
  std::size_t next() const { return next_; }
  bool done() const { return next_ >= frames_.size(); }
  const recording::Frame& frame(std::size_t i) const { return frames_[i]; }

  /// Merges frame next() into the graph. @returns what it changed, with origin_name set to the
  /// frame's origin when it names one (valid until the next step()). @pre !done()
  const graph::ChangeBatch& step();
  /// Steps until frame `i` has been merged (nothing when it already has). @pre i < size()
  void run_through(std::size_t i);

  /// The state after the frames merged so far (the replica id is
  /// recording::replay_replica_id(): it never commits).
  const graph::Graph& graph() const { return *graph_; }

 private:
  std::span<const recording::Frame> frames_;
  std::size_t next_ = 0;
  std::unique_ptr<graph::Graph> graph_;
  graph::Graph::SubscriptionId subscription_ = 0;
  graph::ChangeBatch changes_;
};

}  // namespace quiver::agents::render
