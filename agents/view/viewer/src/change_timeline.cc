// The viewer's timeline: the changes a replica received, listed with what each changed, and the state after any
// of them, both computed by replay when a page asks.
#include "quiver/agents/view/viewer/change_timeline.h"

namespace quiver::agents::inline view::viewer {

using nlohmann::json;

Timeline::Timeline(std::uint64_t max_bytes, std::uint64_t max_changes) : history_(max_bytes, max_changes) {}

void Timeline::add_change(recording::RecordedChange f) {
  states_.push_back(f.delta.kind == graph::GraphDelta::Kind::kState);
  history_.add(std::move(f));
  // The history folds its oldest changes when over its bounds.
  while (states_.size() > history_.end() - history_.begin()) states_.pop_front();
}

json Timeline::entry(std::uint64_t i, const graph::Graph& after, const graph::ChangeBatch& b) const {
  return {{"i", i},
          {"t_ms", static_cast<double>(history_.time_of(i)) / 1e6},
          {"origin", history_.origin_of(i)},
          {"kind", states_[i - history_.begin()] ? "state" : "delta"},
          {"summary", b.empty() ? json(nullptr) : summary_json(after, b)}};
}

json Timeline::list(std::uint64_t from, std::uint64_t limit) const {
  json changes = json::array();
  from = std::max(from, begin());
  if (from < end() && limit > 0) {
    const std::uint64_t last = std::min(end() - 1, from + limit - 1);
    (void)history_.replay(from, last, [&](std::uint64_t i, const graph::Graph& g, const graph::ChangeBatch& b) {
      changes.push_back(entry(i, g, b));
    });
  }
  return {{"begin", begin()}, {"end", end()}, {"frames", changes}};
}

Result<json> Timeline::state_after(std::uint64_t i, const Decor& d) const {
  json j;
  Status s = history_.replay(i, i, [&](std::uint64_t, const graph::Graph& g, const graph::ChangeBatch& b) {
    j = snapshot_json(g, d);
    j["frame"] = entry(i, g, b);
    const json summary = summary_json(g, b);
    j["changed"] = summary["changed"];
    j["changed_edges"] = summary["changed_edges"];
  });
  if (!s.ok()) return s.error();
  return j;
}

}  // namespace quiver::agents::inline view::viewer
