#pragma once
/// @file
/// The simulator's one random fault schedule: packet loss from some time on, partitions that heal,
/// kill -9 and restarts, drawn from a seeded random source (a seed replays exactly) within the
/// bounds a FaultMix sets. Scenarios of every app (Barthel, AGM, a user's) and the replica
/// simulator draw their schedules here.

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "quiver/base/rng.h"
#include "quiver/sim/fault_model.h"

namespace quiver::sim {

struct FaultMix {
  /// Agents a partition splits (each joins one side at random), and agents that may be killed.
  std::vector<std::string> agents, killable;
  using Window = std::pair<double, double>;  ///< [from, to) seconds
  double loss_chance = 0.5;                  ///< a loss episode happens with this probability...
  double max_loss = 0.2;                     ///< ...with a loss drawn in [0, max_loss)
  Window loss_at{0, 10};
  int max_partitions = 2;                    ///< 0..max_partitions two-sided partitions
  Window partition_at{2, 35};
  Window heal_after{0.3, 3};
  int max_kills = 2;                         ///< 0..max_kills kill -9, each restarted
  Window kill_at{1, 35};
  Window restart_after{0.1, 3};
};

/// A schedule drawn from `rng`: a loss episode, partitions each followed by a heal, kills each
/// followed by a restart, in the order drawn (events may overlap; a later partition replaces an
/// earlier one, a heal heals all). A partition one side of which came out empty is left out.
std::vector<FaultEvent> random_faults(Rng& rng, const FaultMix& mix);

}  // namespace quiver::sim
