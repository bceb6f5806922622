#include "quiver/agents/viewer/timeline.h"

namespace quiver::agents::viewer {

using nlohmann::json;

Timeline::Timeline(std::uint64_t max_bytes, std::uint64_t max_frames) : history_(max_bytes, max_frames) {}

void Timeline::add_frame(recording::Frame f) {
  states_.push_back(f.delta.kind == graph::GraphDelta::Kind::kState);
  summaries_.emplace_back();
  history_.add(std::move(f));
  // The history folds its oldest frames when over its bounds.
  while (summaries_.size() > history_.end() - history_.begin()) {
    summaries_.pop_front();
    states_.pop_front();
  }
}

void Timeline::on_batch(const graph::Graph& g, const graph::ChangeBatch& b) {
  if (summaries_.empty()) return;
  summaries_.back() = summary_json(g, b).dump();
}

json Timeline::entry(std::uint64_t i) const {
  const std::size_t k = i - history_.begin();
  return {{"i", i},
          {"t_ms", static_cast<double>(history_.time_of(i)) / 1e6},
          {"origin", history_.origin_of(i)},
          {"kind", states_[k] ? "state" : "delta"},
          {"summary", summaries_[k].empty() ? json(nullptr) : json::parse(summaries_[k])}};
}

json Timeline::list(std::uint64_t from, std::uint64_t limit) const {
  json frames = json::array();
  for (std::uint64_t i = std::max(from, begin()); i < end() && frames.size() < limit; ++i) frames.push_back(entry(i));
  return {{"begin", begin()}, {"end", end()}, {"frames", frames}};
}

Result<json> Timeline::state_after(std::uint64_t i, const Decor& d) const {
  graph::ChangeBatch changes;
  auto g = history_.state_after(i, &changes);
  if (!g.ok()) return g.error();
  json j = snapshot_json(**g, d);
  json s = summary_json(**g, changes);
  j["changed"] = s["changed"];
  j["changed_edges"] = s["changed_edges"];
  j["frame"] = entry(i);
  return j;
}

}  // namespace quiver::agents::viewer
