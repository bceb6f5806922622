// The replica simulator's faults: partitions into groups that later heal, and crashes (kill -9)
// with restarts, drawn at the start of the run.
#include <algorithm>

#include "replica_simulation.h"

namespace quiver::sim {

void Simulation::plan_faults(std::int64_t work_end) {
  if (cfg_.faults.partitions && cfg_.agents >= 2) {
    int episodes = 1 + static_cast<int>(rng_.below(3));
    std::vector<std::int64_t> starts;
    for (int e = 0; e < episodes; ++e) starts.push_back(static_cast<std::int64_t>(rng_.below(work_end)));
    std::sort(starts.begin(), starts.end());
    for (int e = 0; e < episodes; ++e) {
      std::int64_t next = e + 1 < episodes ? starts[e + 1] : work_end;
      std::int64_t len = 50'000'000 + static_cast<std::int64_t>(rng_.below(1'500'000'000));
      std::int64_t end = std::min(starts[e] + len, next);
      int ngroups = 2 + static_cast<int>(rng_.below(std::min(cfg_.agents - 1, 3)));
      std::vector<int> groups(cfg_.agents);
      for (int i = 0; i < cfg_.agents; ++i) groups[i] = i < ngroups ? i : static_cast<int>(rng_.below(ngroups));
      rng_.shuffle(groups);
      net_.at(starts[e], [this, groups] { partition(groups); });
      net_.at(end, [this] {
        net_.heal();
        note("partition healed");
      });
    }
  }
  if (cfg_.faults.crashes) {
    int n = 1 + static_cast<int>(rng_.below(std::max(1, cfg_.agents / 3)));
    for (int k = 0; k < n; ++k) {
      int who = static_cast<int>(rng_.below(cfg_.agents));
      std::int64_t at = static_cast<std::int64_t>(rng_.below(work_end));
      std::int64_t back = at + 20'000'000 + static_cast<std::int64_t>(rng_.below(1'500'000'000));
      if (cfg_.disks.enabled && cfg_.disks.torn_writes && rng_.chance(0.5)) {
        // The power fails during the next write of its store (the host goes down then).
        net_.at(at, [this, who] {
          if (agents_[who].up) agents_[who].disk.tear_next = true;
        });
        continue;
      }
      net_.at(at, [this, who] { crash(who); });
      if (back < work_end)
        net_.at(back, [this, who] {
          if (!agents_[who].up) boot(who);
        });
    }
  }
}

void Simulation::partition(const std::vector<int>& groups) {
  ++result_.partitions;
  std::string split;
  for (int i = 0; i < cfg_.agents; ++i) {
    net_.set_group(i, groups[i]);
    split += (i ? " " : "") + std::to_string(groups[i]);
  }
  note("partition: groups by agent [" + split + "]");
}

}  // namespace quiver::sim
