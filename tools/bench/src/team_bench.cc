// quiver bench team: runs the embedded script and its namespace library with this executable's
// path.
#include "quiver/tools/bench/team_bench.h"

#include <cstdio>
#include <string>
#include <vector>

#include "quiver/agents/runtime/process/embedded_script.h"
#include "quiver/tools/bench/bench_files.h"

namespace quiver::tools::bench {

namespace {

std::string seconds_text(double s) {  // 10, 2.5: what bash passes on as it is
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", s);
  return buf;
}

}  // namespace

int run_team_bench(const TeamBench& b) {
  std::vector<std::string> args = {"--robots", std::to_string(b.robots), "--seconds", seconds_text(b.seconds),
                                   "--nodes", std::to_string(b.nodes)};
  if (!b.out.empty()) args.insert(args.end(), {"--out", b.out});
  return agents::run_embedded_script("quiver bench team",
                                     {{"team_bench.sh", embedded_file("team_bench.sh")}, {"netns.sh", embedded_file("netns.sh")}},
                                     "team_bench.sh", args);
}

}  // namespace quiver::tools::bench
