#pragma once
/// @file
/// The viewer's timeline: the changes a replica received (a bounded recording::History), listed
/// with what each one changed, and the state after any of them. Nothing is computed as changes
/// arrive beyond keeping them: summaries come from replaying the history when a page asks, so a
/// busy domain costs the viewer little.

#include <cstdint>
#include <deque>
#include <string>

#include <nlohmann/json.hpp>

#include "quiver/agents/view/recording/history.h"
#include "quiver/agents/view/viewer/view_json.h"

namespace quiver::agents::inline view::viewer {

class Timeline {
 public:
  explicit Timeline(std::uint64_t max_bytes = 64ull << 20, std::uint64_t max_changes = 200'000);

  /// A change, as it arrives (before the graph merged it).
  void add_change(recording::RecordedChange f);

  std::uint64_t begin() const { return history_.begin(); }
  std::uint64_t end() const { return history_.end(); }
  const recording::History& history() const { return history_; }

  /// {"begin", "end", "frames": [{"i", "t_ms", "origin", "kind", "summary"}...]} for changes
  /// [from, from + limit) that are still listed.
  nlohmann::json list(std::uint64_t from, std::uint64_t limit) const;
  /// The state after change i as snapshot_json(), plus "frame" (its list entry) and "changed"
  /// (node keys) and "changed_edges" for highlighting. kNotFound when i is not listed.
  Result<nlohmann::json> state_after(std::uint64_t i, const Decor& d) const;

 private:
  nlohmann::json entry(std::uint64_t i, const graph::Graph& after, const graph::ChangeBatch& b) const;
  recording::History history_;
  std::deque<bool> states_;  // aligned with history_: change i was a state fragment
};

}  // namespace quiver::agents::inline view::viewer
