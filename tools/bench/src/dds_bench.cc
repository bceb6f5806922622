// The DDS transport benchmark (`quiver bench dds`): the coordinator of its writer, reader and
// joiner processes, and its result line.
#include "quiver/tools/bench/dds_bench.h"

#include <stdlib.h>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <iterator>
#include <map>
#include <memory>

#include "quiver/agents/replica/security/keys.h"
#include "quiver/agents/runtime/process/logging.h"
#include "quiver/tools/bench/attached_viewer.h"
#include "quiver/base/percentiles.h"

namespace quiver::tools::bench {
namespace {

using agents::Subprocess;
using json = nlohmann::json;

// --secure: a fresh CA and one identity per role, in a temporary directory removed at exit.
std::optional<std::string> make_bench_keys(int readers) {
  char tmpl[] = "/tmp/quiver-bench-keys-XXXXXX";
  if (mkdtemp(tmpl) == nullptr) return std::nullopt;
  const std::string dir = tmpl;
  std::vector<std::string> names = {"bench-writer", "bench-joiner"};
  for (int i = 0; i < readers; ++i) names.push_back("bench-reader-" + std::to_string(i));
  Status s = agents::security::init_keys(dir);
  for (const auto& n : names)
    if (s.ok()) s = agents::security::add_agent(dir, n);
  if (!s.ok()) {
    agents::named_logger("bench")->error("--secure: {}", s.error().to_string());
    return std::nullopt;
  }
  return dir;
}

// The medians of each stage of a latency sample, in microseconds: the writer's marks (t0,
// encoded, signed, written) paired by t0 with each reader's (t0, woken, taken, decoded, admitted,
// merging, event). A pair whose marks are out of order (a mark of another sample came between)
// is left out and counted.
json stage_medians(const json& writer, const json& readers) {
  std::map<std::int64_t, std::vector<std::int64_t>> sent;
  for (const auto& w : writer) sent[w[0].get<std::int64_t>()] = w.get<std::vector<std::int64_t>>();
  static constexpr const char* kNames[] = {"commit_and_encode", "sign",     "dds_write", "delivery_and_wakeup",
                                           "take",              "decode",   "admission", "bookkeeping",
                                           "merge_and_events"};
  constexpr std::size_t kSpans = std::size(kNames);
  std::vector<std::vector<double>> spans(kSpans + 1);
  std::size_t skipped = 0, overlapped = 0;
  for (const auto& r : readers) {
    const auto rv = r.get<std::vector<std::int64_t>>();
    auto it = sent.find(rv[0]);
    if (it == sent.end() || rv.size() != 7 || it->second.size() != 4) {
      ++skipped;
      continue;
    }
    // t0, encoded, signed, written (writer), woken, taken, decoded, admitted, merging, event.
    std::vector<std::int64_t> t = it->second;
    t.insert(t.end(), rv.begin() + 1, rv.end());
    // On loopback the reader can wake while the writer is still inside dds_write() (delivery
    // happens within the call): the write then ends, for this sample, when the reader woke, and
    // its delivery takes no time of its own.
    if (t[4] < t[3] && t[4] >= t[2]) {
      t[3] = t[4];
      ++overlapped;
    }
    if (!std::is_sorted(t.begin(), t.end())) {
      ++skipped;
      continue;
    }
    for (std::size_t i = 0; i < kSpans; ++i) spans[i].push_back(static_cast<double>(t[i + 1] - t[i]) / 1e3);
    spans[kSpans].push_back(static_cast<double>(t.back() - t.front()) / 1e3);
  }
  json out;
  for (std::size_t i = 0; i < kSpans; ++i) out[kNames[i]] = round_to(Percentiles(spans[i]).at(0.5), 1);
  out["total"] = round_to(Percentiles(spans[kSpans]).at(0.5), 1);
  out["samples"] = spans[kSpans].size();
  out["skipped"] = skipped;
  out["woken_inside_write"] = overlapped;
  return out;
}

}  // namespace

int run_dds_bench(const DdsBench& b) {
  DdsBench f = b;
  std::shared_ptr<void> cleanup;
  if (f.secure || f.secure_transport) {
    if (f.with_viewer) {
      agents::named_logger("bench")->error("--secure with --with-viewer is not supported");
      return 2;
    }
    auto dir = make_bench_keys(f.readers);
    if (!dir) return 2;
    f.roles.dds.security = *dir;
    cleanup = std::shared_ptr<void>(nullptr, [d = *dir](void*) { std::filesystem::remove_all(d); });
  }
  std::vector<std::string> common = {"--updates",         std::to_string(f.updates),
                                     "--batch",           std::to_string(f.batch),
                                     "--readers",         std::to_string(f.readers),
                                     "--latency-samples", std::to_string(f.latency_samples),
                                     "--join-nodes",      std::to_string(f.join_nodes)};
  if (f.secure_transport) common.push_back("--transport-only");
  if (f.stages) common.push_back("--stages");
  auto readers = spawn_roles(f.roles, "reader", f.readers, common);
  if (!readers) return 2;
  std::unique_ptr<AttachedViewer> viewer;
  if (f.with_viewer) {
    viewer = AttachedViewer::start(f.roles.viewer_exe, f.roles.dds, f.viewer_every_delta);
    if (!viewer) return 2;
  }
  auto writer = Subprocess::spawn(role_argv(f.roles, "writer", common));
  if (!writer) return 2;
  auto ready = read_json(*writer, "writer", 600'000);
  if (!ready) return 1;
  auto joiner = Subprocess::spawn(role_argv(f.roles, "joiner", common));
  if (!joiner) return 2;
  auto joined = read_json(*joiner, "joiner", 120'000);
  std::int64_t t_done = 0;
  std::vector<double> lat;
  json reader_stages = json::array();
  for (int i = 0; i < f.readers; ++i) {
    auto r = read_json((*readers)[i], "reader", 120'000);
    if (!r) return 1;
    t_done = std::max<std::int64_t>(t_done, (*r)["t_throughput_done_ns"].get<std::int64_t>());
    for (double v : (*r)["latencies_us"]) lat.push_back(v);
    if (r->contains("stages"))
      for (auto& s : (*r)["stages"]) reader_stages.push_back(s);
  }
  writer->wait(10'000);
  for (auto& r : *readers) r.wait(10'000);
  joiner->wait(10'000);
  const double secs = static_cast<double>(t_done - (*ready)["t0_ns"].get<std::int64_t>()) / 1e9;
  json out;
  out["bench"] = "dds";
  out["security"] = f.secure ? "dds+signed-deltas" : f.secure_transport ? "dds" : "none";
  out["updates"] = f.updates;
  out["batch"] = f.batch;
  out["readers"] = f.readers;
  out["updates_per_s"] = static_cast<long>(static_cast<double>(f.updates) / secs);
  const Percentiles pct(lat);
  out["latency_us_p50"] = round_to(pct.at(0.50), 1);
  out["latency_us_p99"] = round_to(pct.at(0.99), 1);
  out["latency_samples"] = lat.size();
  out["join_ms_10k"] = joined ? (*joined)["join_ms"] : json(nullptr);
  if (joined) out["join_ms_10k_from_process_start"] = (*joined)["join_ms_from_process_start"];
  out["write_timeouts"] = (*ready)["write_timeouts"];
  out["with_viewer"] = f.with_viewer;
  if (f.with_viewer) out["viewer_every_delta"] = f.viewer_every_delta;
  if (viewer) out["viewer_event_bytes"] = viewer->stop();
  if (f.stages) out["stages_us_p50"] = stage_medians((*ready)["stages"], reader_stages);
  std::cout << out.dump() << std::endl;
  return joined && (*joined)["synced"].get<bool>() ? 0 : 1;
}

}  // namespace quiver::tools::bench
