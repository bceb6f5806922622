// quiver scenario team: runs the embedded choreography (team_scenario.sh) and checks what the
// robots' processes wrote.
#include "quiver/agents/apps/agm/process/team_run.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "quiver/agents/apps/agm/agm_schema.h"
#include "quiver/agents/apps/agm/team_world.h"
#include "quiver/agents/runtime/process/embedded_script.h"
#include "quiver/agents/runtime/process/subprocess.h"
#include "quiver/graph/world_file.h"


namespace quiver::agents::inline apps::agm {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::basic_json<>;  // nlohmann::json

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

// What one process wrote: its JSON lines, in order.
struct ProcessLog {
  std::string name, robot, role;
  std::vector<Json> lines;
  const Json* last_status() const {
    for (auto it = lines.rbegin(); it != lines.rend(); ++it)
      if (it->contains("digest")) return &*it;
    return nullptr;
  }
};

std::vector<ProcessLog> read_logs(const fs::path& out) {
  std::vector<ProcessLog> logs;
  for (const auto& e : fs::directory_iterator(out)) {
    const std::string file = e.path().filename().string();
    if (e.path().extension() != ".log" || file == "faults.log" || file == "dump.log") continue;
    ProcessLog p;
    p.name = e.path().stem().string();
    p.robot = p.name.substr(0, p.name.find('-'));
    p.role = p.name.substr(p.name.find('-') + 1);
    std::ifstream in(e.path());
    for (std::string line; std::getline(in, line);) {
      if (line.empty() || line[0] != '{') continue;
      Json j = Json::parse(line, nullptr, false);
      if (!j.is_discarded()) p.lines.push_back(std::move(j));
    }
    logs.push_back(std::move(p));
  }
  std::sort(logs.begin(), logs.end(), [](const ProcessLog& a, const ProcessLog& b) { return a.name < b.name; });
  return logs;
}

struct Fault {
  std::int64_t t_ns = 0;
  std::string what;
};

std::vector<Fault> read_faults(const fs::path& file) {
  std::vector<Fault> out;
  std::ifstream in(file);
  for (std::string line; std::getline(in, line);) {
    const auto sp = line.find(' ');
    if (sp == std::string::npos) continue;
    out.push_back({std::stoll(line.substr(0, sp)), line.substr(sp + 1)});
  }
  return out;
}

}  // namespace

int run_team_over_dds(const TeamDdsRun& r) {
  const fs::path out = agents::out_dir(r.out, "quiver-team");
  std::vector<std::string> args = {"--out", out.string(), "--robots", std::to_string(r.robots),
                                   "--agents-per-robot", std::to_string(r.agents_per_robot), "--limit", num(r.limit_s)};
  if (r.partition_at_s >= 0) args.insert(args.end(), {"--partition-at", num(r.partition_at_s), "--heal-at", num(r.heal_at_s)});
  if (!r.crash.empty()) args.insert(args.end(), {"--crash", r.crash});
  const int rc = run_embedded_script(
      "quiver scenario team",
      {{"team_scenario.sh", team_files::embedded_file("team_scenario.sh")}, {"netns.sh", team_files::embedded_file("netns.sh")}},
      "team_scenario.sh", args);
  if (rc != 0) return rc;

  const std::vector<ProcessLog> logs = read_logs(out);
  const std::vector<Fault> faults = read_faults(out / "faults.log");
  const std::int64_t t0 = faults.empty() ? 0 : faults.front().t_ns;
  std::vector<std::string> failures;
  auto fail = [&](std::string f) {
    if (failures.size() < 20) failures.push_back(std::move(f));
  };

  // The transcript: faults, drives, grasp events and plans, on the agents' clock.
  std::vector<std::pair<std::int64_t, std::string>> transcript;
  for (const Fault& f : faults) transcript.emplace_back(f.t_ns, f.what);
  std::map<std::string, std::vector<std::pair<std::int64_t, std::int64_t>>> drives;  // robot -> [begin, end]
  struct Carry {
    std::string robot;
    std::int64_t from = 0, to = -1;
  };
  std::map<std::string, std::vector<Carry>> carried;  // object -> who carried it when
  std::map<std::string, std::vector<std::int64_t>> starts;  // robot -> grasp starts
  std::map<std::string, std::string> fetched_by;
  int misses = 0;
  Json joints = Json::object();
  for (const ProcessLog& p : logs) {
    std::string plan_state;
    for (const Json& j : p.lines) {
      if (j.contains("drive")) {
        const auto b = j["drive"].value("begin_ns", std::int64_t{0}), e = j["drive"].value("end_ns", std::int64_t{0});
        drives[p.robot].emplace_back(b, e);
        transcript.emplace_back(b, "robot " + p.robot + " drives (" + num(static_cast<double>(e - b) / 1e9) + " s)");
      }
      if (j.contains("grasp_event")) {
        const Json& g = j["grasp_event"];
        const std::string kind = g.value("kind", ""), object = g.value("object", "");
        const std::int64_t t = g.value("t_ns", std::int64_t{0});
        if (kind == "reach" || kind == "noReach") continue;
        transcript.emplace_back(t, "robot " + p.robot + ": " + kind + " " + object);
        if (kind == "started") starts[p.robot].push_back(t);
        if (kind == "missed") ++misses;
        if (kind == "grasped") {
          carried[object].push_back({p.robot, t, -1});
          fetched_by[object] = p.robot;
        }
        if (kind == "released")
          for (Carry& c : carried[object])
            if (c.robot == p.robot && c.to < 0) c.to = t;
      }
      if (j.contains("planner") && j["planner"].is_string() && !j["planner"].get<std::string>().empty() &&
          j["planner"].get<std::string>() != plan_state) {
        plan_state = j["planner"].get<std::string>();
        transcript.emplace_back(j.value("t_ms", std::int64_t{0}) * 1'000'000, "robot " + p.robot + " plan: " + plan_state);
      }
      if (p.role == "rooms" && j.contains("humans_latency"))
        joints[p.robot] = {{"count", j["humans_latency"].value("count", 0)},
                           {"p50_us", j["humans_latency"].value("p50_us", 0.0)},
                           {"p99_us", j["humans_latency"].value("p99_us", 0.0)}};
    }
  }
  std::sort(transcript.begin(), transcript.end());
  for (const auto& [t, line] : transcript)
    std::printf("[%7.2f s] %s\n", static_cast<double>(t - t0) / 1e9, line.c_str());

  // No mug carried by two robots at once.
  for (const auto& [object, cs] : carried)
    for (std::size_t a = 0; a < cs.size(); ++a)
      for (std::size_t b = a + 1; b < cs.size(); ++b) {
        const auto end = [](const Carry& c) { return c.to < 0 ? INT64_MAX : c.to; };
        if (cs[a].robot != cs[b].robot && cs[a].from < end(cs[b]) && cs[b].from < end(cs[a]))
          fail(object + " was carried by robots " + cs[a].robot + " and " + cs[b].robot + " at once");
      }
  // No grasp started while its robot drove (a drive ends when its robot crashes).
  std::map<std::string, std::int64_t> crashed_at;
  for (const Fault& f : faults)
    if (f.what.rfind("crash: robot ", 0) == 0) crashed_at[f.what.substr(13, 1)] = f.t_ns;
  for (const auto& [robot, ts] : starts)
    for (std::int64_t t : ts)
      for (auto [b, e] : drives[robot]) {
        if (crashed_at.count(robot) && b < crashed_at[robot]) e = std::min(e, crashed_at[robot]);
        if (t > b && t < e) fail("robot " + robot + " started a grasp at " + num(static_cast<double>(t - t0) / 1e9) + " s while it drove");
      }
  // The final graph: every mug in the kitchen, on nothing, carried by no one; every plan achieved.
  auto world = graph::world_seed_file((out / "final.json").string());
  if (!world.ok()) {
    fail("no final graph: " + world.error().to_string());
  } else {
    graph::Graph g(graph::ReplicaId{1, 1});
    g.merge(world->delta);
    const graph::NodeId kitchen = node_id(g, "kitchen");
    for (const char* mug : {"mug", "mug2"}) {
      const graph::NodeId m = node_id(g, mug);
      const auto room = m.is_null() ? std::nullopt : room_of(g, m);
      if (!room || *room != kitchen) fail(std::string(mug) + " does not end in the kitchen");
      if (!m.is_null() && !g.edges_from(m, edge::kOn).empty()) fail(std::string(mug) + " is still on the table");
      if (!m.is_null() && !g.edges_to(m, edge::kCarrying).empty()) fail(std::string(mug) + " is still carried");
    }
    for (const TeamRobot& t : team_robots(r.robots)) {
      const graph::NodeId plan = node_id(g, t.names.plan);
      const graph::Value* v = plan.is_null() ? nullptr : g.attr(plan, "status");
      if (!v || !v->get_if<std::string>() || *v->get_if<std::string>() != "achieved")
        fail("robot " + t.tag + "'s plan is not achieved");
    }
  }
  // Every replica equal at the end: each process's last status line, both sides of each gateway
  // (the tracker is stopped before the others settle: its replica is from when it left).
  std::map<std::string, std::vector<std::string>> digests;
  int processes = 0;
  for (const ProcessLog& p : logs) {
    if (p.role == "humans") continue;
    const Json* s = p.last_status();
    if (!s) {
      fail(p.name + " wrote no status line");
      continue;
    }
    ++processes;
    digests[s->value("digest", "")].push_back(p.name);
    if (s->contains("team_digest")) digests[s->value("team_digest", "")].push_back(p.name + ".team");
  }
  if (digests.size() != 1) {
    std::string d;
    for (const auto& [digest, who] : digests) d += " " + digest.substr(0, 8) + ": " + std::to_string(who.size());
    fail("the replicas ended unequal (digests:" + d + ")");
  }
  for (const TeamRobot& t : team_robots(r.robots))
    if (t.tag != "A" && (!joints.contains(t.tag) || joints[t.tag].value("count", 0) == 0))
      fail("the joints tracked on robot A never reached robot " + t.tag + "'s rooms agent");
  // Healing: from the heal until every gateway hears the others and holds on both sides what
  // the other holds (their status lines, every 250 ms).
  double heal_ms = -1;
  for (const Fault& f : faults) {
    if (f.what.rfind("heal", 0) != 0) continue;
    std::map<std::string, std::int64_t> even_at;
    for (const ProcessLog& p : logs) {
      if (p.role != "gateway") continue;
      for (const Json& j : p.lines)
        if (j.value("t_ms", std::int64_t{0}) * 1'000'000 > f.t_ns && j.value("team_peers", 0) == r.robots - 1 &&
            j.value("even", false)) {
          even_at[p.name] = j.value("t_ms", std::int64_t{0}) * 1'000'000;
          break;
        }
    }
    if (static_cast<int>(even_at.size()) == r.robots) {
      std::int64_t last = 0;
      for (const auto& [name, t] : even_at) last = std::max(last, t);
      heal_ms = static_cast<double>(last - f.t_ns) / 1e6;
    }
  }
  std::uint64_t team_bytes = 0;
  std::ifstream(out / "team_bytes") >> team_bytes;
  Json result = {{"scenario", "team"}, {"robots", r.robots}, {"agents_per_robot", r.agents_per_robot},
                 {"processes", processes}, {"passed", failures.empty()}, {"failures", failures},
                 {"fetched_by", fetched_by}, {"misses", misses}, {"heal_to_even_ms", heal_ms},
                 {"team_bytes", team_bytes}, {"joints_at_other_robots", joints}, {"out", out.string()}};
  std::printf("%s\n", result.dump().c_str());
  return failures.empty() ? 0 : 1;
}

}  // namespace quiver::agents::inline apps::agm
