// The scaling benchmark (`quiver bench scale`): bytes and messages per op per agent as N grows.
#include "quiver/tools/bench/scale_bench.h"

#include <chrono>
#include <iostream>
#include <nlohmann/json.hpp>

#include "quiver/base/percentiles.h"
#include "quiver/sim/simulator.h"
#include "quiver/tools/bench/bench_util.h"

namespace quiver::tools::bench {

int run_scale_bench(const ScaleBench& b) {
  int status = 0;
  for (int n : b.agents) {
    sim::SimConfig c;
    c.agents = n;
    c.steps = b.steps;
    c.seed = b.seed;
    c.idle_ns = static_cast<std::int64_t>(b.idle_s * 1e9);
    c.replicator.gossip = b.protocol == "gossip";
    const auto t0 = std::chrono::steady_clock::now();
    const sim::SimResult r = sim::run_simulation(c);
    const double wall_s = seconds_since(t0);
    const double per = r.ops > 0 ? static_cast<double>(r.ops) * n : 1.0;
    nlohmann::json j = {{"bench", "scale"},
                        {"host", "sim"},
                        {"agents", n},
                        {"steps", b.steps},
                        {"seed", b.seed},
                        {"ops", r.ops},
                        {"bytes", r.bytes},
                        {"messages", r.messages},
                        {"bytes_per_op_per_agent", round_to(static_cast<double>(r.bytes) / per, 1)},
                        {"messages_per_op_per_agent",
                         round_to(static_cast<double>(r.messages) / per, 3)},
                        {"idle_bytes_per_s_per_agent",
                         round_to(static_cast<double>(r.idle_bytes) / (b.idle_s * n), 1)},
                        {"idle_messages_per_s_per_agent",
                         round_to(static_cast<double>(r.idle_messages) / (b.idle_s * n), 2)},
                        {"virtual_ms", r.virtual_ms},
                        {"protocol", b.protocol},
                        {"delta_bytes_per_op_per_receiver",
                         round_to(static_cast<double>(r.by_kind.at("delta").second) /
                                      (static_cast<double>(std::max<std::uint64_t>(1, r.ops)) * std::max(1, n - 1)),
                                  1)},
                        {"protocol_bytes_max", r.protocol_bytes_max},
                        // Peers the network's discovery introduced (DDS's own traffic): not in `bytes`.
                        {"introductions", r.introductions},
                        {"protocol_bytes_mean", r.protocol_bytes_mean},
                        {"converged", r.converged},
                        {"invariant_violations", r.invariant_violations},
                        {"wall_s", round_to(wall_s, 2)}};
    for (const auto& [kind, mb] : r.by_kind)
      if (mb.first > 0) j["by_kind"][kind] = {{"messages", mb.first}, {"bytes", mb.second}};
    if (!b.skip_heal) {
      sim::SimConfig h = c;
      h.idle_ns = 0;
      h.split_until_end = true;
      const sim::SimResult hr = sim::run_simulation(h);
      j["heal_ms"] = hr.settle_ms;
      j["heal_converged"] = hr.converged;
      if (!hr.converged || hr.invariant_violations != 0) status = 1;
    }
    std::cout << j.dump() << std::endl;
    if (!r.converged || r.invariant_violations != 0) status = 1;
  }
  return status;
}

}  // namespace quiver::tools::bench
