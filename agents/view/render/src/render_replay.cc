// A recording replayed in order into one graph, a change at a time, with what each change changed.
#include "quiver/agents/view/render/render_replay.h"

#include <cassert>

#include "quiver/agents/view/recording/history.h"

namespace quiver::agents::inline view::render {

Replay::Replay(std::span<const recording::RecordedChange> changes)
    : recorded_(changes), graph_(std::make_unique<graph::Graph>(recording::replay_replica_id())) {
  // One merge may report its changes in several batches: gather them.
  subscription_ = graph_->subscribe([this](const graph::ChangeBatch& b) {
    changes_.origin = b.origin;
    changes_.origin_name = b.origin_name;
    changes_.nodes.insert(changes_.nodes.end(), b.nodes.begin(), b.nodes.end());
    changes_.edges.insert(changes_.edges.end(), b.edges.begin(), b.edges.end());
  });
}

Replay::~Replay() { graph_->unsubscribe(subscription_); }

const graph::ChangeBatch& Replay::step() {
  assert(!done());
  changes_ = graph::ChangeBatch{};
  const recording::RecordedChange& f = recorded_[next_++];
  graph_->merge(f.delta);
  if (!f.origin.empty()) changes_.origin_name = f.origin;
  return changes_;
}

void Replay::run_through(std::size_t i) {
  while (next_ <= i && !done()) step();
}

}  // namespace quiver::agents::inline view::render
