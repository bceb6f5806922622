#pragma once
/// @file
/// Replays a recording's changes in order into one graph, a change at a time, telling what each
/// one changed. One pass over n changes costs n merges, where History::state_after() rebuilds
/// from the start for each change: the timeline and `quiver render --at N` read states this way.

#include <cstddef>
#include <span>

#include "quiver/agents/view/recording/recorded_change.h"
#include "quiver/graph/graph.h"

namespace quiver::agents::inline view::render {

class Replay {
 public:
  /// @param changes borrowed: they must outlive the Replay.
  explicit Replay(std::span<const recording::RecordedChange> changes);
  ~Replay();
  Replay(const Replay&) = delete;
  Replay& operator=(const Replay&) = delete;

  std::size_t size() const { return recorded_.size(); }
  /// The change step() merges next (size() when done).
  std::size_t next() const { return next_; }
  bool done() const { return next_ >= recorded_.size(); }
  const recording::RecordedChange& change(std::size_t i) const { return recorded_[i]; }

  /// Merges change next() into the graph. @returns what it changed, with origin_name set to the
  /// change's origin when it names one (valid until the next step()). @pre !done()
  const graph::ChangeBatch& step();
  /// Steps until change `i` has been merged (nothing when it already has). @pre i < size()
  void run_through(std::size_t i);

  /// The state after the changes merged so far (the replica id is
  /// recording::replay_replica_id(): it never commits).
  const graph::Graph& graph() const { return *graph_; }

 private:
  std::span<const recording::RecordedChange> recorded_;
  std::size_t next_ = 0;
  std::unique_ptr<graph::Graph> graph_;
  graph::Graph::SubscriptionId subscription_ = 0;
  graph::ChangeBatch changes_;
};

}  // namespace quiver::agents::inline view::render
