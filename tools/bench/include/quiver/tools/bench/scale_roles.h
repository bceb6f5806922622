#pragma once
// The role processes of `quiver bench dds-scale` (`quiver bench-dds-role scale-...`): the writer,
// the members and the joiner. Each prints one JSON line of its results on stdout.

#include <string>

#include "quiver/tools/bench/dds_roles.h"

namespace quiver::tools::bench {

/// One process of `quiver bench dds-scale`.
struct ScaleRole {
  std::string role;  ///< scale-writer, scale-member or scale-joiner
  ReplicaFactory open;
  int id = 0;             ///< members: which one
  int agents = 2;         ///< writer: itself and the members to wait for
  long changes = 1000;    ///< the writer's changes (one node's attributes each)
  double rate = 10;       ///< changes per second
  double idle_s = 10;     ///< idle time (nothing written) over which CPU is measured
  double settle_s = 2;    ///< writer: waits this long after every member joined before writing
};

/// Runs `r.role` and prints its JSON line. @pre r.open is set.
/// @returns 0; 2 when the replica cannot be opened or the role is unknown.
int run_scale_role(const ScaleRole& r);

}  // namespace quiver::tools::bench
