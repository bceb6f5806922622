#pragma once
/// @file
/// How fresh the human models are when an agent sees them: for every RT pose update of a node of
/// type `joint` that reaches the agent (local or merged), now minus the pose's stamp. The human
/// tracker stamps each pose with its clock when it writes it; agent processes on one machine
/// share CLOCK_MONOTONIC, and the simulator's agents its virtual clock, so this is the one-way
/// latency from the tracker's commit to the change event in this agent. Kept as a histogram of
/// 10 µs buckets up to 1 s (beyond: one overflow bucket), exact max.
#include <cstdint>
#include <map>
#include <nlohmann/json_fwd.hpp>

#include "quiver/agents/runtime/api/agent.h"

namespace quiver::agents::inline apps::agm {

class LatencyProbe {
 public:
  /// Subscribes `agent` (in its setup()) to RT changes; samples start `warmup_ns` after now.
  void attach(Agent& agent, AgentContext& ctx, std::int64_t warmup_ns = 500'000'000);
  void record(std::int64_t latency_ns);

  std::uint64_t count() const { return count_; }
  /// Nearest-rank percentile (p in [0, 1]) at 10 µs resolution (the bucket's upper edge), in µs.
  double percentile_us(double p) const;
  double max_us() const { return static_cast<double>(max_ns_) / 1e3; }
  /// {"count", "p50_us", "p99_us", "max_us", "first_ns", "last_ns", "hist_10us": {bucket: n}}.
  void to_json(nlohmann::json& out) const;
  /// Adds a to_json() histogram to this one (pooling several agents' samples).
  void merge_json(const nlohmann::json& in);

 private:
  static constexpr std::int64_t kBucketNs = 10'000;
  static constexpr std::int64_t kBuckets = 100'000;  // 1 s
  std::map<std::int64_t, std::uint64_t> hist_;
  std::uint64_t count_ = 0;
  std::int64_t max_ns_ = 0;
  std::int64_t start_ns_ = 0, first_ns_ = -1, last_ns_ = -1;
};

}  // namespace quiver::agents::inline apps::agm
