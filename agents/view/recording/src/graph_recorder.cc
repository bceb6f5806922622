// What a replica receives turned into recorded changes: every merge, with its time and its origin's name, handed
// to a sink.
#include "quiver/agents/view/recording/graph_recorder.h"

#include <algorithm>
#include <vector>

namespace quiver::agents::inline view::recording {

std::string change_origin(const graph::GraphDelta& d, const std::function<std::string(const graph::ReplicaId&)>& namer) {
  if (d.kind != graph::GraphDelta::Kind::kState) return namer(d.origin);
  std::vector<graph::ReplicaId> who;
  d.for_each_mentioned_dot([&](const graph::Dot& dot) {
    if (who.size() < 8 && std::find(who.begin(), who.end(), dot.replica) == who.end()) who.push_back(dot.replica);
  });
  if (who.empty()) return namer(d.origin);
  std::string out;
  for (const auto& r : who) out += (out.empty() ? "" : ", ") + namer(r);
  return out;
}

GraphRecorder::GraphRecorder(graph::Graph& g, Clock clock, Namer namer, Sink sink)
    : g_(g), clock_(std::move(clock)), namer_(std::move(namer)), sink_(std::move(sink)) {
  if (g_.node_count() > 0 || !g_.context().empty()) {
    sink_(RecordedChange{clock_(), namer_(g_.replica()), g_.state()});
    ++changes_;
  }
  observer_ = g_.add_merge_observer([this](const graph::Graph&, const graph::GraphDelta& d) {
    sink_(RecordedChange{clock_(), change_origin(d, namer_), d});
    ++changes_;
  });
}

GraphRecorder::~GraphRecorder() { g_.remove_merge_observer(observer_); }

}  // namespace quiver::agents::inline view::recording
