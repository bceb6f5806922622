// quiver bench all: every benchmark beside its peer in one run, one JSON file, one page of plots.
#include "quiver/tools/bench/all_bench.h"

#include <signal.h>
#include <sys/utsname.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <optional>
#include <regex>
#include <string>
#include <vector>
#include <nlohmann/json.hpp>

#include "quiver/agents/runtime/process/subprocess.h"
#include "quiver/agents/transport/dds/dds_transport.h"
#include "quiver/tools/bench/bench_files.h"

namespace quiver::tools::bench {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using Env = std::vector<std::pair<std::string, std::string>>;

// One command run to its end: its JSON lines, exit status and seconds.
struct Ran {
  int exit = -1;
  double seconds = 0;
  std::vector<std::string> lines;  // every stdout line
  json results = json::array();    // those that are JSON objects
};

Ran run_command(const std::vector<std::string>& argv, const Env& env, const fs::path& err_log, double timeout_s) {
  Ran r;
  agents::SpawnOptions o;
  o.env = env;
  o.stderr_path = err_log.string();
  o.search_path = true;
  const auto t0 = std::chrono::steady_clock::now();
  auto p = agents::Subprocess::spawn(argv, o);
  if (!p) return r;
  const auto until = t0 + std::chrono::duration<double>(timeout_s);
  while (std::chrono::steady_clock::now() < until) {
    auto line = p->read_line(200);
    if (!line) {
      if (p->wait(0) >= 0) break;  // ended (EOF)
      continue;
    }
    r.lines.push_back(*line);
    if (!line->empty() && line->front() == '{') {
      auto j = json::parse(*line, nullptr, false);
      if (j.is_object()) r.results.push_back(std::move(j));
    }
  }
  r.exit = p->wait(0);
  if (r.exit < 0) {  // still running at the bound
    p->kill(SIGKILL);
    (void)p->wait(5'000);
    r.exit = -1;
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

// The median of the numbers `pattern`'s first group matches in `lines`, or nullopt.
std::optional<double> median_of(const std::vector<std::string>& lines, const std::regex& pattern) {
  std::vector<double> v;
  for (const std::string& l : lines)
    for (std::sregex_iterator it(l.begin(), l.end(), pattern), end; it != end; ++it) v.push_back(std::stod((*it)[1]));
  if (v.empty()) return std::nullopt;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// ddsperf (Cyclone's own tool) between two processes with Quiver's embedded loopback
// configuration: samples/s of 64-byte samples, and the one-way latency (ping/pong, RTT/2).
json run_ddsperf(const AllBench& b, const fs::path& logs, double seconds) {
  json out = {{"peer", "ddsperf"}, {"size", 64}, {"seconds", seconds}};
  agents::DdsConfig cfg;
  const Env env = {{"CYCLONEDDS_URI", agents::loopback_config_xml(cfg)}};
  const std::string domain = std::to_string(b.domain);
  // The server outlives the client by a second; ddsperf reports once a second.
  const std::string d = std::to_string(static_cast<int>(seconds) + 1);
  const std::string d1 = std::to_string(static_cast<int>(seconds));
  auto pair = [&](const char* server, const char* client, const char* log) {
    agents::SpawnOptions o;
    o.env = env;
    o.search_path = true;
    o.stderr_path = (logs / (std::string(log) + ".err")).string();
    auto s = agents::Subprocess::spawn({"ddsperf", "-i", domain, "-D", d, server}, o);
    std::vector<std::string> server_lines;
    if (!s) return std::pair<std::vector<std::string>, std::vector<std::string>>{};
    ::usleep(500'000);
    Ran c = run_command({"ddsperf", "-i", domain, "-D", d1, "-Q", "minmatch:1", client, "size", "64"}, env,
                        logs / (std::string(log) + "-client.err"), seconds + 10);
    while (auto line = s->read_line(static_cast<int>(seconds * 1000) + 5'000)) server_lines.push_back(*line);
    (void)s->wait(5'000);
    return std::pair{server_lines, c.lines};
  };
  auto [sub, pub] = pair("sub", "pub", "ddsperf-sub");
  if (auto rate = median_of(sub, std::regex(R"(rate ([0-9.]+) kS/s)"))) out["samples_per_s"] = *rate * 1000;
  auto [pong, ping] = pair("pong", "ping", "ddsperf-pong");
  if (auto lat = median_of(ping, std::regex(R"(mean ([0-9.]+)us)"))) out["oneway_latency_us"] = *lat;
  return out;
}

const json* first_with(const json& results, const char* key, const std::function<bool(const json&)>& also = nullptr) {
  for (const json& r : results)
    if (r.contains(key) && r[key].is_number() && (!also || also(r))) return &r;
  return nullptr;
}

// One row of the summary: Quiver's figure beside its peer's (ratio = Quiver / peer).
void compare(json& summary, const std::string& figure, const json* ours, const char* our_key, const json* theirs,
             const char* their_key, const std::string& peer, const char* better) {
  if (!ours) return;
  json row = {{"figure", figure}, {"quiver", (*ours)[our_key]}, {"peer", peer}, {"better", better}};
  if (theirs && theirs->contains(their_key) && (*theirs)[their_key].is_number()) {
    row["peer_value"] = (*theirs)[their_key];
    const double p = (*theirs)[their_key].get<double>();
    if (p > 0) row["ratio"] = std::round((*ours)[our_key].get<double>() / p * 1000) / 1000;
  }
  summary.push_back(std::move(row));
}

std::string now_utc() {
  const std::time_t t = std::time(nullptr);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
  return buf;
}

}  // namespace

int run_all_bench(const AllBench& b) {
  const fs::path out = agents::out_dir(b.out, "quiver-bench-all");
  const fs::path logs = out / "logs";
  std::error_code ec;
  fs::create_directories(logs, ec);
  if (ec) {
    std::cerr << "quiver bench all: cannot make " << logs << ": " << ec.message() << "\n";
    return 2;
  }
  const fs::path dir = fs::path(b.quiver).parent_path();
  const std::string domain = std::to_string(b.domain);
  const bool q = b.quick;
  json report = {{"started", now_utc()}, {"quick", q}, {"runs", json::array()}};
  utsname u{};
  if (::uname(&u) == 0) report["host"] = {{"kernel", u.release}, {"machine", u.machine}, {"cores", ::sysconf(_SC_NPROCESSORS_ONLN)}};
  int failures = 0;
  // Runs one command and files it under `name`; absent (with the reason) when `absent` says so.
  auto step = [&](const std::string& name, const std::string& side, std::vector<std::string> argv, const Env& env = {},
                  const std::string& absent = "") -> json {
    json entry = {{"name", name}, {"side", side}, {"command", argv}};
    if (!absent.empty()) {
      entry["absent"] = absent;
      std::cerr << "== " << name << " (" << side << "): absent: " << absent << std::endl;
    } else {
      std::cerr << "== " << name << " (" << side << ")" << std::endl;
      Ran r = run_command(argv, env, logs / (name + "-" + side + ".err"), q ? 300 : 1800);
      entry["exit"] = r.exit;
      entry["seconds"] = std::round(r.seconds * 10) / 10;
      entry["results"] = r.results;
      if (r.exit != 0) {
        ++failures;
        std::cerr << "quiver bench all: '" << name << "' (" << side << ") exited " << r.exit << "; see "
                  << (logs / (name + "-" + side + ".err")).string() << "\n";
      }
    }
    report["runs"].push_back(entry);
    return entry.contains("results") ? entry["results"] : json::array();
  };
  const std::string quiver = b.quiver;

  // DDS: Quiver's replication against Cyclone's own ddsperf, same configuration, same run.
  json dds = step("dds", "quiver",
                  q ? std::vector<std::string>{quiver, "bench", "dds", "--domain", domain, "--batch", "1", "--readers", "1",
                                               "--updates", "2000", "--latency-samples", "200", "--join-nodes", "1000", "--stages"}
                    : std::vector<std::string>{quiver, "bench", "dds", "--domain", domain, "--batch", "1", "--readers", "1",
                                               "--stages"});
  json ddsperf;
  {
    agents::SpawnOptions quiet;
    quiet.stderr_path = "/dev/null";
    quiet.search_path = true;
    const bool have = agents::Subprocess::spawn({"ddsperf", "-h"}, quiet).has_value();
    json entry = {{"name", "dds"}, {"side", "ddsperf"}};
    if (!have) {
      entry["absent"] = "ddsperf is not installed (Debian: cyclonedds-tools)";
    } else {
      std::cerr << "== dds (ddsperf)" << std::endl;
      ddsperf = run_ddsperf(b, logs, q ? 2 : 8);
      entry["results"] = json::array({ddsperf});
      if (!ddsperf.contains("samples_per_s") || !ddsperf.contains("oneway_latency_us")) ++failures;
    }
    report["runs"].push_back(entry);
  }

  // The CRDT alone: Quiver against Yjs, the same workload, batches of 1 and 100.
  const Env node_env = {{"NODE_PATH", "/usr/share/nodejs"}};
  std::string no_yjs;
  const fs::path yjs_script = out / "yjs_crdt.js";
  {
    std::ofstream(yjs_script) << embedded_file("yjs_crdt.js");
    Ran probe = run_command({"node", "-e", "require('yjs')"}, node_env, logs / "yjs-probe.err", 30);
    if (probe.exit != 0) no_yjs = "node or Debian's node-yjs is not installed (apt install nodejs node-yjs)";
  }
  json crdt_rows = json::array();
  for (const int batch : {1, 100}) {
    const std::string updates = q ? "20000" : batch == 1 ? "300000" : "1000000";
    const std::string name = "crdt-batch-" + std::to_string(batch);
    json ours = step(name, "quiver", {quiver, "bench", "crdt", "--batch", std::to_string(batch), "--updates", updates});
    json theirs = step(name, "yjs", {"node", yjs_script.string(), "1000", "10", updates, std::to_string(batch), "1"}, node_env, no_yjs);
    crdt_rows.push_back({{"batch", batch}, {"quiver", ours}, {"yjs", theirs}});
  }

  // Transforms: Quiver's frame tree against tf2 (quiver_bench_tf2, built beside quiver with libtf2-dev).
  const std::string tf2 = (dir / "quiver_bench_tf2").string();
  const std::vector<std::string> tf_args = {"--lookups", q ? "20000" : "1000000"};
  std::vector<std::string> ours_tf = {quiver, "bench", "transforms"}, theirs_tf = {tf2};
  ours_tf.insert(ours_tf.end(), tf_args.begin(), tf_args.end());
  theirs_tf.insert(theirs_tf.end(), tf_args.begin(), tf_args.end());
  json tf_ours = step("transforms", "quiver", ours_tf);
  json tf_theirs = step("transforms", "tf2", theirs_tf, {},
                        ::access(tf2.c_str(), X_OK) == 0 ? "" : "quiver_bench_tf2 is not built (Debian: libtf2-dev)");

  // Quiver alone: memory, agent processes, many agents.
  json memory = step("memory", "quiver", {quiver, "bench", "memory", "--nodes", q ? "1000" : "10000", "--runs", q ? "1" : "3"});
  json footprint = step("footprint", "quiver", {quiver, "bench", "footprint", "--runs", q ? "1" : "3", "--settle", q ? "1.5" : "4",
                                                "--domain", std::to_string(b.domain + 1)});
  json scale = step("scale", "quiver",
                    q ? std::vector<std::string>{quiver, "bench", "scale", "--agents", "4,8", "--steps", "200", "--no-heal"}
                      : std::vector<std::string>{quiver, "bench", "scale", "--agents", "4,16,64,256"});

  // The summary: each figure beside its peer's.
  json summary = json::array();
  const json* d = first_with(dds, "latency_us_p50");
  compare(summary, "DDS latency p50 (us), one change", d, "latency_us_p50", ddsperf.is_null() ? nullptr : &ddsperf,
          "oneway_latency_us", "ddsperf one-way", "lower");
  compare(summary, "DDS delivered updates/s, unbatched", d, "updates_per_s", ddsperf.is_null() ? nullptr : &ddsperf,
          "samples_per_s", "ddsperf samples/s (64 B)", "higher");
  if (d && d->contains("join_ms_10k") && (*d)["join_ms_10k"].is_number())
    compare(summary, "late join of a 10k-node world (ms)", d, "join_ms_10k", nullptr, "", "none", "lower");
  for (const json& row : crdt_rows) {
    const std::string batch = std::to_string(row["batch"].get<int>());
    const json* ours = first_with(row["quiver"], "local_ops_per_s");
    const json* theirs = first_with(row["yjs"], "local_ops_per_s");
    compare(summary, "CRDT local writes/s, transactions of " + batch, ours, "local_ops_per_s", theirs, "local_ops_per_s", "Yjs",
            "higher");
    compare(summary, "CRDT remote applies/s, transactions of " + batch, ours, "remote_apply_ops_per_s", theirs,
            "remote_apply_ops_per_s", "Yjs", "higher");
    compare(summary, "CRDT bytes per update, transactions of " + batch, ours, "bytes_per_update", theirs, "bytes_per_update", "Yjs",
            "lower");
  }
  for (const char* mode : {"latest", "interpolated"}) {
    auto is_mode = [mode](const json& r) { return r.value("mode", "") == mode; };
    compare(summary, std::string("transform lookups/s, ") + mode, first_with(tf_ours, "lookups_per_s", is_mode), "lookups_per_s",
            first_with(tf_theirs, "lookups_per_s", is_mode), "lookups_per_s", "tf2", "higher");
  }
  const json* agent = first_with(footprint, "rss_kb_p50", [](const json& r) { return r.value("variant", "") == "quiver agent"; });
  const json* whole = first_with(footprint, "rss_kb_p50", [](const json& r) { return r.value("variant", "") != "quiver agent"; });
  compare(summary, "resident kB of quiver agent (kitchen world)", agent, "rss_kb_p50", whole, "rss_kb_p50",
          "the same inside the whole quiver", "lower");
  report["summary"] = summary;
  report["finished"] = now_utc();

  const fs::path file = out / "bench.json";
  std::ofstream(file) << report.dump(1) << "\n";
  if (!fs::exists(file)) {
    std::cerr << "quiver bench all: cannot write " << file << "\n";
    return 2;
  }
  // The page: matplotlib draws the plots (python3-matplotlib); without it the page says so.
  const fs::path plot = out / "plot_bench.py";
  std::ofstream(plot) << embedded_file("plot_bench.py");
  // Debian's interpreter, where python3-matplotlib installs, before another python3 in PATH.
  const std::string python = ::access("/usr/bin/python3", X_OK) == 0 ? "/usr/bin/python3" : "python3";
  Ran page = run_command({python, plot.string(), file.string(), out.string()}, {}, logs / "plot.err", 120);
  if (page.exit != 0) {
    std::ofstream(out / "index.html") << "<!doctype html><meta charset=utf-8><title>quiver bench all</title>"
                                         "<p>The plots could not be drawn (python3 with python3-matplotlib is needed; see logs/plot.err). "
                                         "The figures are in <a href=bench.json>bench.json</a>.</p>\n";
    std::cerr << "quiver bench all: no plots (see " << (logs / "plot.err").string() << ")\n";
  }
  for (const json& row : summary) {
    json line = row;
    line["bench"] = "all";
    std::cout << line.dump() << "\n";
  }
  std::cout << json{{"bench", "all"}, {"report", file.string()}, {"page", (out / "index.html").string()}, {"failures", failures}}.dump()
            << std::endl;
  return failures == 0 ? 0 : 1;
}

}  // namespace quiver::tools::bench
