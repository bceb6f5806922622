// `quiver bench humans`: the human-tracking load (2 people x 15 joints x 30 Hz) reaching the
// other AGM agents, one process each, while they work.
#include <unistd.h>

#include <cmath>
#include <iostream>

#include "quiver/agents/apps/agm/agm_roles.h"
#include "quiver/agents/apps/agm/agm_schema.h"
#include "quiver/agents/apps/agm/latency_probe.h"
#include "quiver/agents/apps/agm/process/agm_runs.h"
#include "quiver/agents/runtime/process/logging.h"

namespace quiver::agents::inline apps::agm {
namespace {

using json = nlohmann::json;

double seconds_between(const json& status) {
  return static_cast<double>(status["last_ns"].get<std::int64_t>() -
                             status["first_ns"].get<std::int64_t>()) /
         1e9;
}

}  // namespace

int run_humans_bench(const HumansBench& b) {
  auto log = named_logger("quiver bench humans");
  AgmProcessOptions po = b.processes;
  po.out = out_dir(po.out, "quiver-bench-humans");
  AgmProcesses procs(po);
  std::vector<std::string> others = {"navigation", "rooms", "grasping"};
  if (!b.no_planner) others.push_back(kPlannerRole);
  // With the planner (the default): the clean-the-table mission, the planner agent planning
  // and tracking the plan, navigation and grasping following it.
  std::vector<std::string> mission;
  if (!b.no_planner) mission = {"--mission", kCleanTable};
  auto with = [&](std::vector<std::string> a) {
    a.insert(a.end(), mission.begin(), mission.end());
    return a;
  };
  for (const auto& r : others)
    if (!procs.start(r, with({"--measure-humans"}))) {
      log->error("cannot start {} run {}", po.exe, r);
      return 2;
    }
  // The others join and warm up (their probes start 0.5 s after their setup) before tracking.
  ::usleep(3'000'000);
  if (!procs.start("humans", with({}))) return 2;
  ::usleep(static_cast<useconds_t>((1.0 + b.seconds) * 1e6));  // 1 s: the tracker's own join wait
  auto humans = procs.stop("humans");
  ::usleep(300'000);
  LatencyProbe pooled;
  json per_agent = json::object();
  std::uint64_t deliveries = 0;
  double delivery_secs = 0;
  std::map<std::string, int> exit_statuses;
  json planner_status;
  for (const auto& r : others) {
    auto st = procs.stop(r);
    if (r == kPlannerRole && st)
      for (const char* k : {"planner", "plans", "replans", "exit_status"})
        if (st->contains(k)) planner_status[k] = (*st)[k];
    if (!st || !st->contains("humans_latency")) {
      log->error("no status from {}", r);
      return 1;
    }
    exit_statuses[r] = st->value("exit_status", -1);
    const json& h = (*st)["humans_latency"];
    pooled.merge_json(h);
    deliveries += h["count"].get<std::uint64_t>();
    if (h["last_ns"].get<std::int64_t>() > h["first_ns"].get<std::int64_t>())
      delivery_secs = std::max(delivery_secs, seconds_between(h));
    per_agent[r] = {{"poses", h["count"]},
                    {"p50_us", h["p50_us"]},
                    {"p99_us", h["p99_us"]},
                    {"max_us", h["max_us"]}};
  }
  json res;
  res["bench"] = "humans";
  res["people"] = 2;
  res["joints"] = 15;
  res["hz"] = 30;
  res["receivers"] = others;
  if (humans) {
    const double secs = seconds_between(*humans);
    res["seconds"] = std::round(secs * 100) / 100;
    res["rt_updates_per_s"] =
        secs > 0 ? std::lround((*humans)["rt_updates"].get<double>() / secs) : 0;
    res["transactions_per_s"] =
        secs > 0 ? std::lround(2 * (*humans)["frames"].get<double>() / secs) : 0;
  }
  res["deliveries"] = deliveries;
  res["deliveries_per_s_per_agent"] =
      delivery_secs > 0
          ? std::lround(static_cast<double>(deliveries) / others.size() / delivery_secs)
          : 0;
  res["latency_us_p50"] = pooled.percentile_us(0.50);
  res["latency_us_p99"] = pooled.percentile_us(0.99);
  res["latency_us_max"] = pooled.max_us();
  res["per_agent"] = per_agent;
  res["p99_limit_ms"] = b.max_p99_ms;
  bool clean = humans && humans->value("exit_status", -1) == 0;
  for (const auto& r : others) clean = clean && exit_statuses[r] == 0;
  if (!b.no_planner) {
    res["planner"] = planner_status;
    res["mission"] = kCleanTable;
  }
  res["agents_exited_cleanly"] = clean;
  const bool ok = clean && deliveries > 0 && pooled.percentile_us(0.99) <= b.max_p99_ms * 1e3;
  res["ok"] = ok;
  std::cout << res.dump() << std::endl;
  return ok ? 0 : 1;
}

}  // namespace quiver::agents::inline apps::agm
