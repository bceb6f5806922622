#pragma once
/// @file
/// A bounded, in-memory history of changes that can rebuild the state after any of them (a
/// viewer's timeline, a renderer of a recording).
///
/// Changes are numbered from 0 in arrival order; numbers stay valid while the history runs. When
/// the changes kept pass `max_bytes` (their encoded size) or `max_changes`, the oldest are folded
/// into a base state, so the earliest change still listed moves on but every listed one can still be
/// rebuilt.

#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "quiver/agents/view/recording/recorded_change.h"
#include "quiver/graph/graph.h"
#include "quiver/base/result.h"

namespace quiver::agents::inline view::recording {

class History {
 public:
  explicit History(std::uint64_t max_bytes = 64ull << 20, std::uint64_t max_changes = UINT64_MAX);
  ~History();
  History(History&&) noexcept;
  History& operator=(History&&) noexcept;

  /// Appends a change (numbered end() - 1 afterwards).
  void add(RecordedChange f);
  /// The first change still listed, and one past the last.
  std::uint64_t begin() const { return first_; }
  std::uint64_t end() const { return first_ + kept_.size(); }
  bool empty() const { return kept_.empty(); }
  std::uint64_t bytes() const { return bytes_; }
  /// Changes folded into the base state so far.
  std::uint64_t folded() const { return first_; }

  /// RecordedChange `i` (decoded again from its stored bytes). kNotFound when i is not listed.
  Result<RecordedChange> change(std::uint64_t i) const;
  /// Time and origin of change i without decoding its delta.
  std::int64_t time_of(std::uint64_t i) const;
  const std::string& origin_of(std::uint64_t i) const;

  /// A graph holding the state after change `i` (the base state, then changes begin()..i), and,
  /// if `changes` is given, what change i changed. kNotFound when i is not listed.
  Result<std::unique_ptr<graph::Graph>> state_after(std::uint64_t i,
                                                    graph::ChangeBatch* changes = nullptr) const;
  /// Rebuilds the states after changes begin()..last in order and calls `fn(i, graph after i,
  /// what change i changed)` for each i >= `from`. kNotFound when `last` is not listed.
  using ReplayFn =
      std::function<void(std::uint64_t, const graph::Graph&, const graph::ChangeBatch&)>;
  Status replay(std::uint64_t from, std::uint64_t last, const ReplayFn& fn) const;

 private:
  // replay() into `g` (empty), which holds the state after `last` when it returns.
  Status replay_into(graph::Graph& g, std::uint64_t from, std::uint64_t last,
                     const ReplayFn& fn) const;
  struct Kept {
    std::int64_t t_ns;
    std::string origin;
    std::vector<std::uint8_t> delta;  // graph codec
  };
  std::uint64_t max_bytes_;
  std::uint64_t max_changes_;
  std::uint64_t first_ = 0;
  std::uint64_t bytes_ = 0;
  std::deque<Kept> kept_;
  std::unique_ptr<graph::Graph> base_;
};

/// The replica id the graphs rebuilt from recordings use as their own (they never commit).
graph::ReplicaId replay_replica_id();

}  // namespace quiver::agents::inline view::recording
