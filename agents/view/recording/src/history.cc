// A bounded in-memory history of changes that rebuilds the state after any of them, the oldest folded into a
// base state.
#include "quiver/agents/view/recording/history.h"

#include "quiver/graph/codec.h"
#include "quiver/base/hash.h"

namespace quiver::agents::inline view::recording {

graph::ReplicaId replay_replica_id() { return graph::ReplicaId{fnv1a64("quiver-replay"), 1}; }

History::History(std::uint64_t max_bytes, std::uint64_t max_changes)
    : max_bytes_(max_bytes), max_changes_(max_changes) {}
History::~History() = default;
History::History(History&&) noexcept = default;
History& History::operator=(History&&) noexcept = default;

void History::add(RecordedChange f) {
  Kept k{f.t_ns, std::move(f.origin), graph::encode(f.delta)};
  bytes_ += k.delta.size() + k.origin.size();
  kept_.push_back(std::move(k));
  while ((bytes_ > max_bytes_ || kept_.size() > max_changes_) && kept_.size() > 1) {
    Kept& old = kept_.front();
    if (!base_) base_ = std::make_unique<graph::Graph>(replay_replica_id());
    // Stored bytes came from encode() of a delta that was merged once already: they decode.
    if (auto d = graph::decode(old.delta); d.ok()) base_->merge(d.value());
    bytes_ -= old.delta.size() + old.origin.size();
    kept_.pop_front();
    ++first_;
  }
}

Result<RecordedChange> History::change(std::uint64_t i) const {
  if (i < first_ || i >= end())
    return make_error(ErrorCode::kNotFound,
                      "frame " + std::to_string(i) + " is not in the history (it holds " +
                          std::to_string(first_) + ".." + std::to_string(end()) + ")");
  const Kept& k = kept_[i - first_];
  auto d = graph::decode(k.delta);
  if (!d.ok()) return d.error();
  return RecordedChange{k.t_ns, k.origin, std::move(d.value())};
}

std::int64_t History::time_of(std::uint64_t i) const { return kept_.at(i - first_).t_ns; }
const std::string& History::origin_of(std::uint64_t i) const { return kept_.at(i - first_).origin; }

Status History::replay_into(graph::Graph& g, std::uint64_t from, std::uint64_t last,
                            const ReplayFn& fn) const {
  if (last < first_ || last >= end())
    return make_error(ErrorCode::kNotFound,
                      "frame " + std::to_string(last) + " is not in the history (it holds " +
                          std::to_string(first_) + ".." + std::to_string(end()) + ")");
  if (base_) g.merge(base_->state());
  graph::ChangeBatch changes;
  const auto sub = g.subscribe([&changes](const graph::ChangeBatch& b) { changes = b; });
  graph::GraphDelta d;
  Status status;
  for (std::uint64_t j = first_; j <= last && status.ok(); ++j) {
    status = graph::decode(kept_[j - first_].delta, d);
    if (!status.ok()) break;
    changes = graph::ChangeBatch{};
    g.merge(d);
    if (j >= from) {
      changes.origin_name = kept_[j - first_].origin;
      fn(j, g, changes);
    }
  }
  g.unsubscribe(sub);
  return status;
}

Status History::replay(std::uint64_t from, std::uint64_t last, const ReplayFn& fn) const {
  graph::Graph g(replay_replica_id());
  return replay_into(g, from, last, fn);
}

Result<std::unique_ptr<graph::Graph>> History::state_after(std::uint64_t i,
                                                           graph::ChangeBatch* changes) const {
  auto g = std::make_unique<graph::Graph>(replay_replica_id());
  Status s =
      replay_into(*g, i, i, [&](std::uint64_t, const graph::Graph&, const graph::ChangeBatch& b) {
        if (changes != nullptr) *changes = b;
      });
  if (!s.ok()) return s.error();
  return g;
}

}  // namespace quiver::agents::inline view::recording
