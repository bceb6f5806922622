#pragma once
/// @file
/// The simulator's one random fault schedule: packet loss from some time on, partitions that heal,
/// kill -9 and restarts, drawn from a seeded random source (a seed replays exactly) within the
/// bounds a FaultMix sets. Scenarios of every app (Barthel, AGM, a user's) and the replica
/// simulator draw their schedules here.

#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "quiver/base/rng.h"
#include "quiver/sim/fault_model.h"

namespace quiver::sim {

/// The bounds of a random schedule. A count or a group number with one possible value is taken
/// without a draw, so a mix that leaves a kind of fault out draws nothing for it.
struct FaultMix {
  /// Agents a partition splits, and agents that may be killed.
  std::vector<std::string> agents, killable;
  using Window = std::pair<double, double>;  ///< [from, to) seconds
  double loss_chance = 0.5;                  ///< a loss episode happens with this probability...
  double max_loss = 0.2;                     ///< ...with a loss drawn in [0, max_loss)
  Window loss_at{0, 10};
  int min_partitions = 0;                    ///< min_partitions..max_partitions partitions
  int max_partitions = 2;
  /// A partition splits `agents` into 2..max_groups groups (no more groups than agents).
  int max_groups = 2;
  /// Each group gets an agent first, the others join groups at random: no group is empty and no
  /// partition is left out. Otherwise every agent joins a group at random, and a partition with
  /// an empty group is left out.
  bool fill_groups = false;
  /// Partitions come one after another: in order of time, each heals at the latest when the next
  /// begins, the last at the latest at the end of partition_at. Otherwise they may overlap (a
  /// later partition replaces an earlier one, a heal heals all).
  bool partitions_in_turn = false;
  Window partition_at{2, 35};
  Window heal_after{0.3, 3};
  int min_kills = 0;                         ///< min_kills..max_kills kill -9, each restarted...
  int max_kills = 2;
  Window kill_at{1, 35};
  Window restart_after{0.1, 3};
  /// ...unless the restart would come at or after this time: then it is left out (the host
  /// restarts the agent itself, e.g. when the faults end).
  double restarts_until = std::numeric_limits<double>::infinity();
};

/// A schedule drawn from `rng`: a loss episode, partitions each followed by a heal, kills each
/// followed by a restart, in the order drawn (events may overlap; a later partition replaces an
/// earlier one, a heal heals all), or with partitions_in_turn, partitions in order of time.
std::vector<FaultEvent> random_faults(Rng& rng, const FaultMix& mix);

}  // namespace quiver::sim
