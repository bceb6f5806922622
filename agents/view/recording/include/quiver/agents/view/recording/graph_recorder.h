#pragma once
/// @file
/// Turns what a replica receives into changes: every merge into the graph (a peer's delta, a
/// state transfer) becomes one RecordedChange, handed to a sink (a RecordWriter, a History) with its time
/// and its origin's name. The first change is the replica's state when recording began (if it
/// holds anything), so that a recording replays on its own.
///
/// Local commits are not recorded (recorders are observers); the same graph may carry other
/// merge observers (a grammar guard).

#include <cstdint>
#include <functional>
#include <string>

#include "quiver/agents/view/recording/recorded_change.h"
#include "quiver/graph/graph.h"

namespace quiver::agents::inline view::recording {

/// Who made what a merged fragment carries: its origin's name for a delta; for a state (a join, a
/// sampling observer's pull) the names of the replicas whose dots it adds, in order of first
/// mention ("writer, person"), or its sender's name if it adds none.
std::string change_origin(const graph::GraphDelta& d, const std::function<std::string(const graph::ReplicaId&)>& namer);

class GraphRecorder {
 public:
  using Clock = std::function<std::int64_t()>;
  using Namer = std::function<std::string(const graph::ReplicaId&)>;
  using Sink = std::function<void(RecordedChange&&)>;
  /// `clock` gives the changes' times (ns); `namer` names an origin (e.g. Replicator::name_of).
  GraphRecorder(graph::Graph& g, Clock clock, Namer namer, Sink sink);
  ~GraphRecorder();
  GraphRecorder(const GraphRecorder&) = delete;
  GraphRecorder& operator=(const GraphRecorder&) = delete;

  std::uint64_t changes() const { return changes_; }

 private:
  graph::Graph& g_;
  Clock clock_;
  Namer namer_;
  Sink sink_;
  graph::Graph::ObserverId observer_ = 0;
  std::uint64_t changes_ = 0;
};

}  // namespace quiver::agents::inline view::recording
