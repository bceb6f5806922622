// The one random fault schedule of the simulator.
#include "quiver/sim/fault_generator.h"

#include <algorithm>

namespace quiver::sim {
namespace {

// A count in [lo, hi]; no draw when there is one choice (or none: lo).
int count_in(Rng& rng, int lo, int hi) {
  if (hi <= lo) return lo;
  return lo + static_cast<int>(rng.below(static_cast<std::uint64_t>(hi - lo) + 1));
}

// `agents` split into `n` groups as FaultMix::fill_groups says; empty when a group came out empty.
std::vector<std::vector<std::string>> split(Rng& rng, const std::vector<std::string>& agents, int n, bool fill) {
  std::vector<int> group(agents.size());
  if (fill) {
    if (agents.size() < static_cast<std::size_t>(n)) return {};
    for (std::size_t i = 0; i < agents.size(); ++i)
      group[i] = i < static_cast<std::size_t>(n) ? static_cast<int>(i) : static_cast<int>(rng.below(n));
    rng.shuffle(group);
  } else {
    for (int& g : group) g = static_cast<int>(rng.below(n));
  }
  std::vector<std::vector<std::string>> groups(n);
  for (std::size_t i = 0; i < agents.size(); ++i) groups[group[i]].push_back(agents[i]);
  for (const auto& g : groups)
    if (g.empty()) return {};
  return groups;
}

}  // namespace

std::vector<FaultEvent> random_faults(Rng& rng, const FaultMix& mix) {
  std::vector<FaultEvent> out;
  auto at = [&](const FaultMix::Window& w) { return w.first + rng.uniform() * (w.second - w.first); };
  if (mix.loss_chance > 0 && rng.chance(mix.loss_chance)) {
    FaultEvent e;
    e.kind = FaultEvent::Kind::kLoss;
    e.at_s = at(mix.loss_at);
    e.loss = mix.max_loss * rng.uniform();
    out.push_back(e);
  }
  const int partitions = count_in(rng, mix.min_partitions, mix.max_partitions);
  std::vector<std::pair<FaultEvent, double>> splits;  // each with its heal time
  for (int p = 0; p < partitions; ++p) {
    const int most = std::min(mix.max_groups, static_cast<int>(mix.agents.size()));
    FaultEvent e;
    e.kind = FaultEvent::Kind::kPartition;
    e.groups = split(rng, mix.agents, count_in(rng, 2, most), mix.fill_groups);
    if (e.groups.empty()) continue;
    e.at_s = at(mix.partition_at);
    const double heal_at = e.at_s + at(mix.heal_after);
    splits.emplace_back(e, heal_at);
  }
  if (mix.partitions_in_turn) {
    std::stable_sort(splits.begin(), splits.end(),
                     [](const auto& a, const auto& b) { return a.first.at_s < b.first.at_s; });
    for (std::size_t p = 0; p < splits.size(); ++p)
      splits[p].second =
          std::min(splits[p].second, p + 1 < splits.size() ? splits[p + 1].first.at_s : mix.partition_at.second);
  }
  for (const auto& [e, heal_at] : splits) {
    out.push_back(e);
    FaultEvent h;
    h.kind = FaultEvent::Kind::kHeal;
    h.at_s = heal_at;
    out.push_back(h);
  }
  const int kills = count_in(rng, mix.min_kills, mix.max_kills);
  for (int k = 0; k < kills && !mix.killable.empty(); ++k) {
    FaultEvent e;
    e.kind = FaultEvent::Kind::kKill;
    e.agent = mix.killable[rng.below(mix.killable.size())];
    e.at_s = at(mix.kill_at);
    out.push_back(e);
    FaultEvent r = e;
    r.kind = FaultEvent::Kind::kRestart;
    r.at_s = e.at_s + at(mix.restart_after);
    if (r.at_s < mix.restarts_until) out.push_back(r);
  }
  return out;
}

}  // namespace quiver::sim
