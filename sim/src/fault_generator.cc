// The one random fault schedule of the simulator.
#include "quiver/sim/fault_generator.h"

namespace quiver::sim {

std::vector<FaultEvent> random_faults(Rng& rng, const FaultMix& mix) {
  std::vector<FaultEvent> out;
  auto at = [&](const FaultMix::Window& w) { return w.first + rng.uniform() * (w.second - w.first); };
  if (rng.chance(mix.loss_chance)) {
    FaultEvent e;
    e.kind = FaultEvent::Kind::kLoss;
    e.at_s = at(mix.loss_at);
    e.loss = mix.max_loss * rng.uniform();
    out.push_back(e);
  }
  const int partitions = static_cast<int>(rng.below(static_cast<std::uint64_t>(mix.max_partitions) + 1));
  for (int p = 0; p < partitions; ++p) {
    std::vector<std::string> a, b;
    for (const auto& n : mix.agents) (rng.chance(0.5) ? a : b).push_back(n);
    if (a.empty() || b.empty()) continue;
    FaultEvent e;
    e.kind = FaultEvent::Kind::kPartition;
    e.at_s = at(mix.partition_at);
    e.groups = {a, b};
    out.push_back(e);
    FaultEvent h;
    h.kind = FaultEvent::Kind::kHeal;
    h.at_s = e.at_s + at(mix.heal_after);
    out.push_back(h);
  }
  const int kills = static_cast<int>(rng.below(static_cast<std::uint64_t>(mix.max_kills) + 1));
  for (int k = 0; k < kills && !mix.killable.empty(); ++k) {
    FaultEvent e;
    e.kind = FaultEvent::Kind::kKill;
    e.agent = mix.killable[rng.below(mix.killable.size())];
    e.at_s = at(mix.kill_at);
    out.push_back(e);
    FaultEvent r = e;
    r.kind = FaultEvent::Kind::kRestart;
    r.at_s = e.at_s + at(mix.restart_after);
    out.push_back(r);
  }
  return out;
}

}  // namespace quiver::sim
