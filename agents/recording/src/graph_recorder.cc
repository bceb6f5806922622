#include "quiver/agents/recording/graph_recorder.h"

namespace quiver::agents::recording {

GraphRecorder::GraphRecorder(graph::Graph& g, Clock clock, Namer namer, Sink sink)
    : g_(g), clock_(std::move(clock)), namer_(std::move(namer)), sink_(std::move(sink)) {
  if (g_.node_count() > 0 || !g_.context().empty()) {
    sink_(Frame{clock_(), namer_(g_.replica()), g_.state()});
    ++frames_;
  }
  observer_ = g_.add_merge_observer([this](const graph::Graph&, const graph::GraphDelta& d) {
    sink_(Frame{clock_(), namer_(d.origin), d});
    ++frames_;
  });
}

GraphRecorder::~GraphRecorder() { g_.remove_merge_observer(observer_); }

}  // namespace quiver::agents::recording
