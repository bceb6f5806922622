// `quiver bench dds-scale`: the coordinator of its writer, member and joiner processes, and its
// result lines (one per number of agents).
#include "quiver/tools/bench/dds_scale_bench.h"

#include <algorithm>
#include <iostream>
#include <nlohmann/json.hpp>

#include "quiver/agents/runtime/process/logging.h"
#include "quiver/base/percentiles.h"
#include "quiver/tools/bench/bench_util.h"

namespace quiver::tools::bench {

using agents::Subprocess;
using json = nlohmann::json;

namespace {

json one_run(const DdsScaleBench& b, int n, bool& ok) {
  const std::vector<std::string> common = {"--agents", std::to_string(n), "--changes", std::to_string(b.changes),
                                           "--rate", std::to_string(b.rate), "--idle", std::to_string(b.idle_s),
                                           "--settle", std::to_string(b.settle_s)};
  json out{{"bench", "dds-scale"}, {"agents", n},       {"membership", b.roles.dds.membership},
           {"lease_s", b.roles.dds.lease_s}, {"changes", b.changes}, {"rate", b.rate}};
  auto members = spawn_roles(b.roles, "scale-member", n - 1, common, b.start_gap_ms);
  auto writer = Subprocess::spawn(role_argv(b.roles, "scale-writer", common));
  if (!members || !writer) {
    ok = false;
    return out;
  }
  const int budget_ms =
      static_cast<int>((static_cast<double>(b.changes) / b.rate + b.idle_s + b.settle_s + 400) * 1000);
  auto w = read_json(*writer, "writer", budget_ms);
  std::vector<double> all, last;
  std::vector<double> last_of(static_cast<std::size_t>(b.changes), 0);
  std::vector<int> got(static_cast<std::size_t>(b.changes), 0);
  std::vector<double> cpu_run, cpu_idle, rss;
  bool complete = w.has_value();
  for (auto& m : *members) {
    auto r = complete ? read_json(m, "member", 60'000) : std::nullopt;
    if (!r) {
      complete = false;
      continue;
    }
    const auto& l = (*r)["latencies_us"];
    for (std::size_t i = 0; i < l.size() && i < last_of.size(); ++i) {
      const double v = l[i].get<double>();
      if (v < 0) continue;
      all.push_back(v);
      last_of[i] = std::max(last_of[i], v);
      ++got[i];
    }
    cpu_run.push_back((*r)["cpu_run_pct"].get<double>());
    cpu_idle.push_back((*r)["cpu_idle_pct"].get<double>());
    rss.push_back((*r)["rss_kb"].get<double>());
    out["member_executable"] = (*r)["executable"];
  }
  std::optional<json> j;
  if (complete) {
    auto joiner = Subprocess::spawn(role_argv(b.roles, "scale-joiner", common));
    if (joiner) {
      j = read_json(*joiner, "joiner", 180'000);
      joiner->wait(10'000);
    }
  }
  for (auto& m : *members)
    if (m.wait(10'000) < 0) m.kill(9);
  if (writer->wait(10'000) < 0) writer->kill(9);
  long missing = 0;
  for (std::size_t i = 0; i < got.size(); ++i) {
    if (got[i] == n - 1) last.push_back(last_of[i]);
    else missing += (n - 1) - got[i];
  }
  const auto mean = [](const std::vector<double>& v) {
    double s = 0;
    for (double x : v) s += x;
    return v.empty() ? 0.0 : s / static_cast<double>(v.size());
  };
  const auto max = [](const std::vector<double>& v) { return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end()); };
  if (w) {
    out["ready_ms"] = round_to((*w)["ready_ms"].get<double>(), 1);
    out["all_joined"] = (*w)["all_joined"];
    out["writer_peers_lost"] = (*w)["peers_lost"];
    cpu_run.push_back((*w)["cpu_run_pct"].get<double>());
    cpu_idle.push_back((*w)["cpu_idle_pct"].get<double>());
    out["delivered_updates_per_s"] = round_to(static_cast<double>(all.size()) / (*w)["run_s"].get<double>(), 1);
  }
  const Percentiles pa(all), pl(last);
  out["latency_ms_p50"] = round_to(pa.at(0.50) / 1e3, 3);
  out["latency_ms_p99"] = round_to(pa.at(0.99) / 1e3, 3);
  out["last_of_others_ms_p50"] = round_to(pl.at(0.50) / 1e3, 3);
  out["last_of_others_ms_p90"] = round_to(pl.at(0.90) / 1e3, 3);
  out["last_of_others_ms_p99"] = round_to(pl.at(0.99) / 1e3, 3);
  out["last_of_others_ms_max"] = round_to(max(last) / 1e3, 3);
  out["deliveries"] = all.size();
  out["missing"] = missing;
  out["cpu_run_pct_mean"] = round_to(mean(cpu_run), 2);
  out["cpu_run_pct_max"] = round_to(max(cpu_run), 2);
  out["cpu_idle_pct_mean"] = round_to(mean(cpu_idle), 2);
  out["cpu_idle_pct_max"] = round_to(max(cpu_idle), 2);
  out["rss_mb_mean"] = round_to(mean(rss) / 1024, 1);
  out["join_ms"] = j ? (*j)["join_ms"] : json(nullptr);
  out["completed"] = complete && j && (*j)["synced"].get<bool>() && missing == 0;
  if (!out["completed"].get<bool>()) ok = false;
  return out;
}

}  // namespace

int run_dds_scale_bench(const DdsScaleBench& b) {
  bool ok = true;
  for (int n : b.agents) std::cout << one_run(b, n, ok).dump() << std::endl;
  return ok ? 0 : 1;
}

}  // namespace quiver::tools::bench
