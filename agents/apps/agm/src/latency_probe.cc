// The latency probe: how long a tracked pose took to reach this agent (p50/p99/max).
#include "quiver/agents/apps/agm/latency_probe.h"

#include <algorithm>
#include <nlohmann/json.hpp>
#include <string>

namespace quiver::agents::inline apps::agm {

void LatencyProbe::attach(Agent& agent, AgentContext& ctx, std::int64_t warmup_ns) {
  start_ns_ = ctx.now() + warmup_ns;
  ChangeFilter f;
  f.edge_types = {"RT"};
  agent.subscribe(f, [this](AgentContext& c, const graph::ChangeBatch& b) {
    const std::int64_t now = c.now();
    if (now < start_ns_ || b.local) return;
    const graph::Graph& g = c.graph();
    const graph::Symbol joint("joint");
    for (const graph::EdgeChange& e : b.edges) {
      if (e.kind != graph::ChangeKind::kUpdated || g.type_of(e.key.to) != joint) continue;
      if (auto rt = g.rt_edge(e.key.to); rt && rt->stamp > 0) {
        record(now - rt->stamp);
        if (first_ns_ < 0) first_ns_ = now;
        last_ns_ = now;
      }
    }
  });
}

void LatencyProbe::record(std::int64_t latency_ns) {
  const std::int64_t l = std::max<std::int64_t>(0, latency_ns);
  ++hist_[std::min(l / kBucketNs, kBuckets)];
  ++count_;
  max_ns_ = std::max(max_ns_, l);
}

double LatencyProbe::percentile_us(double p) const {
  if (count_ == 0) return 0;
  const auto rank = static_cast<std::uint64_t>(p * static_cast<double>(count_ - 1) + 0.5) + 1;
  std::uint64_t seen = 0;
  for (const auto& [bucket, n] : hist_) {
    seen += n;
    if (seen >= rank)
      return std::min(static_cast<double>((bucket + 1) * kBucketNs), static_cast<double>(max_ns_)) /
             1e3;
  }
  return max_us();
}

void LatencyProbe::to_json(nlohmann::json& out) const {
  out["count"] = count_;
  out["p50_us"] = percentile_us(0.50);
  out["p99_us"] = percentile_us(0.99);
  out["max_us"] = max_us();
  out["first_ns"] = first_ns_;
  out["last_ns"] = last_ns_;
  nlohmann::json h = nlohmann::json::object();
  for (const auto& [bucket, n] : hist_) h[std::to_string(bucket)] = n;
  out["hist_10us"] = h;
}

void LatencyProbe::merge_json(const nlohmann::json& in) {
  if (!in.is_object() || !in.contains("hist_10us")) return;
  for (auto it = in["hist_10us"].begin(); it != in["hist_10us"].end(); ++it) {
    const std::uint64_t n = it.value().get<std::uint64_t>();
    hist_[std::stoll(it.key())] += n;
    count_ += n;
  }
  max_ns_ =
      std::max<std::int64_t>(max_ns_, static_cast<std::int64_t>(in.value("max_us", 0.0) * 1e3));
}

}  // namespace quiver::agents::inline apps::agm
