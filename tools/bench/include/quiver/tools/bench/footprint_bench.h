#pragma once
// What an agent process costs the robot at rest (`quiver bench footprint`): resident memory and
// the shared objects it maps, for `quiver agent` (which becomes the lean quiver-agent), the same
// command kept inside the whole `quiver`, and each Barthel role in quiver-barthel.

#include <cstdint>
#include <string>

namespace quiver::tools::bench {

struct FootprintBench {
  std::string quiver;  ///< the quiver executable (quiver-agent and quiver-barthel beside it)
  /// `quiver agent`'s world file; empty: examples/worlds/kitchen.json when it is there (from the
  /// source tree), else none.
  std::string world;
  int runs = 3;            ///< medians over this many processes per variant are reported
  double settle_s = 4;     ///< measured this long after the start
  std::uint32_t domain = 83;
};

/// Starts each variant's process `runs` times on loopback, reads /proc/PID/status (VmRSS,
/// RssAnon, RssFile) and /proc/PID/maps after `settle_s`, stops it, and prints one JSON line per
/// variant: medians in kB, the executable the process ran, how many shared objects it mapped and
/// which of OpenCV, Graphviz, Python and VTK among them.
/// @returns 0, or 2 when a process cannot be started or ends before it is measured.
int run_footprint_bench(const FootprintBench& b);

}  // namespace quiver::tools::bench
