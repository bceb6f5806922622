// `quiver bench schedules`: seeded fault schedules at one number of agents, counted.
#include "quiver/tools/bench/schedules_bench.h"

#include <algorithm>
#include <chrono>
#include <iostream>
#include <nlohmann/json.hpp>

#include "quiver/base/percentiles.h"
#include "quiver/sim/simulator.h"
#include "quiver/tools/bench/bench_util.h"

namespace quiver::tools::bench {

int run_schedules_bench(const SchedulesBench& b) {
  std::uint64_t converged = 0, diverged = 0, violations = 0, rejected = 0, crashes = 0, partitions = 0;
  std::uint64_t dropped = 0, with_loss = 0, failed = 0;
  std::int64_t overlap_ns = 0, max_settle = 0;
  const auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < b.count; ++i) {
    sim::SimConfig c = sim::mixed_config(b.seed + static_cast<std::uint64_t>(i), b.steps);
    c.agents = b.agents;
    c.faults.loss = std::min(c.faults.loss, b.max_loss);
    c.replicator.gossip = b.protocol == "gossip";
    const sim::SimResult r = sim::run_simulation(c);
    converged += r.converged ? 1 : 0;
    violations += r.invariant_violations;
    rejected += r.rejected_samples;
    overlap_ns += r.lock_overlap_connected_ns;
    crashes += r.crashes;
    partitions += r.partitions;
    dropped += r.dropped;
    with_loss += c.faults.loss > 0 ? 1 : 0;
    max_settle = std::max(max_settle, r.settle_ms);
    diverged += r.converged ? 0 : 1;
    if (!r.ok()) {
      ++failed;
      std::cerr << "schedule " << c.seed << " failed (replay: quiver bench schedules --agents " << b.agents
                << " --count 1 --seed " << c.seed << " --steps " << b.steps << "): " << r.to_json() << "\n";
    }
  }
  const nlohmann::json j = {{"bench", "schedules"},
                            {"host", "sim"},
                            {"protocol", b.protocol},
                            {"agents", b.agents},
                            {"schedules", b.count},
                            {"seed", b.seed},
                            {"steps", b.steps},
                            {"max_loss", b.max_loss},
                            {"converged", converged},
                            {"diverged", diverged},
                            {"failed", failed},
                            {"invariant_violations", violations},
                            {"rejected_samples", rejected},
                            {"lock_overlap_connected_ms", round_to(static_cast<double>(overlap_ns) / 1e6, 3)},
                            {"schedules_with_loss", with_loss},
                            {"crashes", crashes},
                            {"partitions", partitions},
                            {"packets_dropped", dropped},
                            {"settle_ms_max", max_settle},
                            {"wall_s", round_to(seconds_since(t0), 1)}};
  std::cout << j.dump() << std::endl;
  return failed == 0 ? 0 : 1;
}

}  // namespace quiver::tools::bench
