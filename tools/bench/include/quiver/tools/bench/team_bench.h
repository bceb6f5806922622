#pragma once
/// @file
/// `quiver bench team` (issue 23, docs/teams.md "Traffic between robots"): robots as network
/// namespaces the benchmark makes itself (root only; nothing is sent outside them), each with its
/// gateway; the human tracker on one robot and the joints' latency on the others, the bytes on the
/// team network against the delta bytes the tracker publishes, and a robot joining a large world
/// late. The run is a bash script (tools/bench/team/team_bench.sh, with scripts/netns.sh) embedded
/// in the binary, so that an installed `quiver` has it too.
#include <string>
#include <string_view>

namespace quiver::tools::bench {

struct TeamBench {
  int robots = 3;
  double seconds = 10;
  int nodes = 10'000;
  std::string out;  ///< keep the logs here (default: a temporary directory, removed)
};

/// Runs the benchmark; its JSON line goes to stdout. @returns 0 when every target is met, 1 when
/// one is not, 77 without root (the script says why), 2 when it cannot start.
int run_team_bench(const TeamBench& b);

}  // namespace quiver::tools::bench
