#pragma once
/// @file
/// `quiver scenario team` (issue 23, docs/teams.md "The team scenario"): the team scenario of
/// seed 001's world with real processes, each robot a network namespace the run makes itself
/// (root only; nothing is sent outside them) with its gateway and agents on its own loopback
/// domain, each with a store (--durability always). The choreography is a bash script embedded in
/// the binary (team/team_scenario.sh, with scripts/netns.sh): start the robots, cut the team link
/// and heal it, crash a robot (SIGKILL of all its processes) and restart it from its stores, stop
/// once every robot's plan is achieved. Then this checks what the processes wrote — their grasp
/// events, their drives, their final status lines — and the final graph, prints a transcript,
/// and ends with one JSON line.
#include <string>
#include <string_view>

namespace quiver::agents::inline apps::agm {

namespace team_files {
/// The embedded team_scenario.sh and netns.sh ("" for another name).
std::string_view embedded_file(std::string_view name);
}  // namespace team_files

struct TeamDdsRun {
  int robots = 2;
  int agents_per_robot = 6;  ///< gateway included (see TeamScenario)
  /// The team link is cut at partition_at_s and healed at heal_at_s (seconds from the start; a
  /// negative partition_at_s: never, `--no-partition`).
  double partition_at_s = 12, heal_at_s = 22;
  /// "B@16": robot B crashes 16 s after the start and comes back 2 s later ("": none).
  std::string crash = "B@16";
  double limit_s = 120;
  std::string out;  ///< the logs, stores and final graph (default: /tmp/quiver-team-XXXXXX, kept)
};

/// Runs it. @returns 0 when every check holds, 1 when one fails, 77 without root (the script says
/// why), 2 when it cannot start.
int run_team_over_dds(const TeamDdsRun& r);

}  // namespace quiver::agents::inline apps::agm
