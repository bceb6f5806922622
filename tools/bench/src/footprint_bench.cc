// quiver bench footprint: resident memory and mapped libraries of agent processes at rest.
#include "quiver/tools/bench/footprint_bench.h"

#include <signal.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <set>
#include <sstream>
#include <thread>
#include <vector>
#include <nlohmann/json.hpp>

#include "quiver/agents/runtime/process/subprocess.h"
#include "quiver/base/percentiles.h"

namespace quiver::tools::bench {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

struct Variant {
  std::string name;
  std::vector<std::string> argv;
  std::vector<std::pair<std::string, std::string>> env;
};

struct Sample {
  double rss_kb = 0, anon_kb = 0, file_kb = 0;
  std::string exe;
  std::set<std::string> objects;  // the shared objects mapped (file names)
};

double status_kb(const std::string& status, const std::string& key) {
  std::istringstream in(status);
  for (std::string line; std::getline(in, line);)
    if (line.rfind(key + ":", 0) == 0) return std::stod(line.substr(key.size() + 1));
  return 0;
}

std::optional<Sample> measure(pid_t pid) {
  const std::string proc = "/proc/" + std::to_string(pid);
  std::ifstream st(proc + "/status");
  if (!st) return std::nullopt;
  std::stringstream status;
  status << st.rdbuf();
  Sample s;
  s.rss_kb = status_kb(status.str(), "VmRSS");
  s.anon_kb = status_kb(status.str(), "RssAnon");
  s.file_kb = status_kb(status.str(), "RssFile");
  std::error_code ec;
  s.exe = fs::read_symlink(proc + "/exe", ec).filename().string();
  std::ifstream maps(proc + "/maps");
  for (std::string line; std::getline(maps, line);) {
    const auto slash = line.rfind('/');
    if (slash == std::string::npos || line.find(".so", slash) == std::string::npos) continue;
    s.objects.insert(line.substr(slash + 1));
  }
  return s;
}


}  // namespace

int run_footprint_bench(const FootprintBench& b) {
  const fs::path dir = fs::path(b.quiver).parent_path();
  const std::string barthel = (dir / "quiver-barthel").string();
  const std::string domain = std::to_string(b.domain);
  std::string world = b.world;
  if (world.empty() && fs::exists("examples/worlds/kitchen.json")) world = "examples/worlds/kitchen.json";
  std::vector<std::string> agent = {b.quiver, "agent", "--name", "footprint", "--domain", domain};
  if (!world.empty()) agent.insert(agent.end(), {"--world", world});
  std::vector<Variant> variants = {
      {"quiver agent", agent, {}},
      {"quiver agent, inside quiver", agent, {{"QUIVER_IN_ONE_EXECUTABLE", "1"}}},
  };
  for (const char* role : {"planner", "speech", "panel", "person", "patient"})
    variants.push_back({std::string("quiver-barthel run ") + role,
                        {barthel, "run", role, "--simulated-speech", "--domain", domain}, {}});
  const std::vector<std::string> heavy = {"libopencv", "libgvc", "libcgraph", "libpython", "libvtk"};
  for (const Variant& v : variants) {
    std::vector<double> rss, anon, file;
    Sample last;
    for (int r = 0; r < b.runs; ++r) {
      agents::SpawnOptions o;
      o.env = v.env;
      o.stderr_path = "/dev/null";
      auto p = agents::Subprocess::spawn(v.argv, o);
      if (!p) {
        std::cerr << "bench footprint: cannot start " << v.argv[0] << "\n";
        return 2;
      }
      const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(b.settle_s);
      while (std::chrono::steady_clock::now() < until) (void)p->read_line(50);  // keep its stdout drained
      auto s = measure(p->pid());
      p->kill(SIGTERM);
      (void)p->wait(10'000);
      if (!s || s->rss_kb <= 0) {
        std::cerr << "bench footprint: '" << v.name << "' ended before it was measured\n";
        return 2;
      }
      rss.push_back(s->rss_kb);
      anon.push_back(s->anon_kb);
      file.push_back(s->file_kb);
      last = *s;
    }
    json heavy_mapped = json::array();
    for (const std::string& h : heavy)
      if (std::any_of(last.objects.begin(), last.objects.end(), [&](const std::string& o) { return o.rfind(h, 0) == 0; }))
        heavy_mapped.push_back(h);
    std::cout << json{{"bench", "footprint"},           {"variant", v.name}, {"world", world.empty() ? json(nullptr) : json(world)},
                      {"executable", last.exe},         {"runs", b.runs},
                      {"settle_s", b.settle_s},         {"rss_kb_p50", median(rss)},
                      {"rss_anon_kb_p50", median(anon)}, {"rss_file_kb_p50", median(file)},
                      {"shared_objects", last.objects.size()}, {"heavy_libraries", heavy_mapped}}
                     .dump()
              << std::endl;
  }
  return 0;
}

}  // namespace quiver::tools::bench
