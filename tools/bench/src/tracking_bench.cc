// The human-tracking DDS benchmark (`quiver bench dds-tracking`): the coordinator of its tracker
// and listener processes, and its result line.
#include "quiver/tools/bench/tracking_bench.h"

#include <iostream>
#include <memory>

#include "quiver/tools/bench/attached_viewer.h"
#include "quiver/base/percentiles.h"

namespace quiver::tools::bench {

using agents::Subprocess;
using json = nlohmann::json;

int run_tracking_bench(const TrackingBench& f) {
  std::vector<std::string> common = {"--agents", std::to_string(f.agents), "--seconds",
                                     std::to_string(f.seconds)};
  auto listeners = spawn_roles(f.roles, "listener", f.agents - 1, common);
  if (!listeners) return 2;
  std::unique_ptr<AttachedViewer> viewer;
  if (f.with_viewer &&
      !(viewer = AttachedViewer::start(f.roles.viewer_exe, f.roles.dds, f.viewer_every_delta)))
    return 2;
  auto tracker = Subprocess::spawn(role_argv(f.roles, "tracker", common));
  if (!tracker) return 2;
  auto t = read_json(*tracker, "tracker", static_cast<int>((f.seconds + 120) * 1000));
  if (!t) return 1;
  std::vector<double> lat;
  for (auto& l : *listeners) {
    auto r = read_json(l, "listener", 30'000);
    if (!r) return 1;
    for (double v : (*r)["latencies_us"]) lat.push_back(v);
  }
  json out;
  out["bench"] = "dds-tracking";
  out["agents"] = f.agents;
  out["rt_updates_per_s"] = static_cast<long>((*t)["updates"].get<long>() / f.seconds);
  out["deliveries"] = lat.size();
  const Percentiles pct(lat);
  out["latency_us_p50"] = round_to(pct.at(0.50), 1);
  out["latency_us_p99"] = round_to(pct.at(0.99), 1);
  out["latency_us_max"] = round_to(pct.at(1.0), 1);
  out["with_viewer"] = f.with_viewer;
  if (f.with_viewer) out["viewer_every_delta"] = f.viewer_every_delta;
  if (viewer) out["viewer_event_bytes"] = viewer->stop();
  std::cout << out.dump() << std::endl;
  return 0;
}

}  // namespace quiver::tools::bench
