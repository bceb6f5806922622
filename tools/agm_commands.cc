// quiver scenario agm (the AGM scenarios of seed 001 — navigation, robot-in-room, grasping and
// human tracking — one process per agent over DDS on loopback, checked from an observer replica)
// and quiver bench humans (the human-tracking load reaching the other agents while they work).
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <csignal>
#include <cstdio>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>

#include "bench_stats.h"
#include "commands.h"
#include "dds_options.h"
#include "quiver/agents/apps/agm/clean_table.h"
#include "quiver/agents/apps/agm/agm_roles.h"
#include "quiver/agents/apps/agm/agm_schema.h"
#include "quiver/agents/runtime/process/logging.h"
#include "subprocess.h"

namespace quiver::tools {

std::string self_executable();

namespace {

namespace agm = agents::agm;
using graph::NodeId;
using json = nlohmann::json;
constexpr std::int64_t kMs = 1'000'000;
constexpr std::int64_t kSec = 1'000'000'000;

// The AGM agents as processes (`quiver run ROLE`), their stderr in OUT/logs/ROLE.log.
class AgmProcesses {
 public:
  AgmProcesses(const DdsFlags& dds, std::string out)
      : dds_(dds), out_(std::move(out)), exe_(self_executable()) {
    ::mkdir(out_.c_str(), 0755);
    ::mkdir((out_ + "/logs").c_str(), 0755);
  }
  ~AgmProcesses() {
    for (auto& [name, p] : procs_) p.kill(SIGTERM);
    for (auto& [name, p] : procs_) p.wait(5000);
  }
  bool start(const std::string& role, std::vector<std::string> extra) {
    std::vector<std::string> argv = {
        exe_,           "run",           role,          "--domain", std::to_string(dds_.domain),
        "--dds-config", dds_.dds_config, "--join-wait", "1"};
    argv.insert(argv.end(), extra.begin(), extra.end());
    const int n = ++starts_[role];
    auto p = Subprocess::spawn(
        argv, out_ + "/logs/" + role + (n > 1 ? "-" + std::to_string(n) : "") + ".log");
    if (!p) return false;
    args_[role] = extra;
    procs_.erase(role);
    procs_.emplace(role, std::move(*p));
    return true;
  }
  /// kill -9 (and reap). @returns its pid, or -1.
  int kill(const std::string& role) {
    auto it = procs_.find(role);
    if (it == procs_.end()) return -1;
    it->second.kill(SIGKILL);
    it->second.wait(2000);
    return it->second.pid();
  }
  /// Starts `role` again, with the arguments it had (a new incarnation, an empty replica).
  bool restart(const std::string& role) { return start(role, args_[role]); }
  /// SIGTERM, wait, and the last JSON line it printed (its final status), with its exit status
  /// as "exit_status" (-1: it did not end).
  std::optional<json> stop(const std::string& role) {
    auto it = procs_.find(role);
    if (it == procs_.end()) return std::nullopt;
    it->second.kill(SIGTERM);
    std::optional<json> last;
    for (int i = 0; i < 100; ++i) {
      while (auto line = it->second.read_line(100)) {
        auto j = json::parse(*line, nullptr, false);
        if (j.is_object()) last = std::move(j);
      }
      if (last) break;
    }
    const int status = it->second.wait(5000);
    if (last) (*last)["exit_status"] = status;
    procs_.erase(it);
    return last;
  }

 private:
  DdsFlags dds_;
  std::string out_, exe_;
  std::map<std::string, Subprocess> procs_;
  std::map<std::string, std::vector<std::string>> args_;
  std::map<std::string, int> starts_;
};

std::string make_out(const std::string& out, const char* prefix) {
  if (!out.empty()) return out;
  std::string tmpl = std::string("/tmp/") + prefix + "-XXXXXX";
  if (!mkdtemp(tmpl.data())) return "/tmp";
  return tmpl;
}

template <class T>
T edge_attr_or(const graph::Graph& g, const graph::EdgeKey& k, const char* name, T fallback) {
  const graph::Value* v = g.edge_attr(k, name);
  const T* p = v ? v->get_if<T>() : nullptr;
  return p ? *p : fallback;
}

// ------------------------------------------------------------------ quiver scenario agm

struct AgmScenarioFlags {
  DdsFlags dds;
  std::string out;
  double timeout_s = 150;
  double crossing_lag_ms = 100;
  double motion_allowance_ms = 150;
  std::string kill;  ///< kill -9 this agent at kill_at_s and restart it restart_after_s later
  double kill_at_s = 12;
  double restart_after_s = 1;
  std::string mission;  ///< "" or clean-table
};

// quiver scenario agm --mission clean-table: the planner agent as a fifth process; navigation
// and grasping follow its plan. Checked on the observer's final replica: the mission holds, the
// plan is achieved, the first plan replays through the grammar guard, each mug grasped and
// released once, replicas equal.
int run_agm_clean_table(const AgmScenarioFlags& f) {
  auto log = agents::named_logger("quiver scenario");
  if (!f.kill.empty()) {
    // A navigation process restarted mid-mission would start a new platform at the start pose.
    log->error("--kill is not supported with --mission clean-table (docs/scenarios.md, limits)");
    return 2;
  }
  const std::string out = make_out(f.out, "quiver-agm-clean-table");
  agents::DdsReplicaOptions o;
  o.name = "agm-observer";
  o.observer = true;
  auto created = f.dds.create_agent(o);
  if (!created.ok()) {
    log->error("{}", created.error().to_string());
    return 2;
  }
  agents::DdsReplica& obs = **created;
  graph::Graph& g = obs.graph();
  const std::int64_t t_start = agents::monotonic_ns();
  auto elapsed = [&] { return static_cast<double>(agents::monotonic_ns() - t_start) / 1e9; };
  auto say = [&](const std::string& line) {
    std::printf("[%6.2f s] %s\n", elapsed(), line.c_str());
    std::fflush(stdout);
  };
  std::map<std::int64_t, std::string> plans;
  std::map<std::string, int> grasped, released;
  int room_changes = 0, carrying_now = 0, max_carrying = 0;
  std::string last_next;
  std::vector<std::string> failures;
  g.subscribe([&](const graph::ChangeBatch& b) {
    const NodeId robot = agm::node_id(g, agm::node::kRobot);
    if (robot.is_null()) return;
    for (const graph::EdgeChange& e : b.edges) {
      if (e.key.from != robot) continue;
      const std::string type(e.key.type.str()), to = g.name_of(e.key.to);
      const bool made = e.kind == graph::ChangeKind::kCreated,
                 gone = e.kind == graph::ChangeKind::kDeleted;
      if (type == agm::edge::kIn && made && g.edge_attr(e.key, "committed_ns")) {
        ++room_changes;
        say("changeRoom -> " + to);
      } else if (type == agm::edge::kReach && made && g.edge_attr(e.key, "distance")) {
        say("reach " + to);
      } else if (type == agm::edge::kCarrying && made) {
        ++grasped[to];
        max_carrying = std::max(max_carrying, ++carrying_now);
        say("grasped " + to + " (off the table)");
      } else if (type == agm::edge::kCarrying && gone) {
        ++released[to];
        --carrying_now;
        say("released " + to);
      }
    }
    const NodeId plan = agm::node_id(g, "plan");
    if (plan.is_null()) return;
    auto v = g.get<std::int64_t>(plan, "version");
    auto steps = g.get<std::string>(plan, "steps");
    if (v.ok() && steps.ok() && !steps->empty() && !plans.count(*v)) {
      plans[*v] = *steps;
      say("plan " + std::to_string(*v) + " written by the planner agent:\n" + *steps);
    }
    auto status = g.get<std::string>(plan, "status");
    auto next = g.get<std::int64_t>(plan, "next");
    const std::string now_next = (status.ok() ? *status : "") + " " +
                                 (next.ok() ? std::to_string(*next + 1) : "");
    if (now_next != last_next) {
      last_next = now_next;
      if (auto st = agm::next_plan_step(g))
        say("plan: next step " + std::to_string(st->index + 1) + " (" + st->rule + ")");
      else if (status.ok())
        say("plan: " + *status);
    }
  });

  std::printf(
      "Clean the table over Cyclone DDS (domain %u, loopback): the planner agent, navigation, "
      "rooms, grasping and humans, one process each, no executive.\nLogs: %s/logs/\n\n",
      f.dds.domain, out.c_str());
  AgmProcesses procs(f.dds, out);
  const std::vector<std::string> mission = {"--mission", agm::kCleanTable};
  auto with = [&](std::vector<std::string> a) {
    a.insert(a.end(), mission.begin(), mission.end());
    return a;
  };
  if (!procs.start("navigation", with({"--measure-humans", "--quiet-when-done"})) ||
      !procs.start("rooms", with({"--measure-humans"})) ||
      !procs.start("grasping", with({"--measure-humans"})) ||
      !procs.start(agm::kPlannerRole, with({"--measure-humans"})) ||
      !procs.start("humans", with({}))) {
    log->error("cannot start {} run ROLE", self_executable());
    return 2;
  }
  const std::int64_t deadline = t_start + static_cast<std::int64_t>(f.timeout_s * 1e9);
  std::int64_t achieved_at = -1;
  while (agents::monotonic_ns() < deadline) {
    obs.spin_once(20 * kMs);
    const NodeId plan = agm::node_id(g, "plan"), robot = agm::node_id(g, agm::node::kRobot);
    auto status = plan.is_null() ? Result<std::string>(make_error(ErrorCode::kNotFound, "plan"))
                                 : g.get<std::string>(plan, "status");
    const bool achieved = status.ok() && *status == "achieved";
    if (!achieved) {
      achieved_at = -1;
      continue;
    }
    if (achieved_at < 0) achieved_at = agents::monotonic_ns();
    if (!robot.is_null() && !g.has_edge(robot, robot, agm::edge::kMoved) &&
        agents::monotonic_ns() > achieved_at + 2 * kSec)
      break;
  }
  if (achieved_at < 0)
    failures.push_back("the plan was not achieved within " + std::to_string(f.timeout_s) + " s");

  auto humans = procs.stop("humans");
  obs.spin_for(500 * kMs);
  std::map<std::string, json> finals;
  for (const char* role : {"navigation", "rooms", "grasping", agm::kPlannerRole})
    if (auto st = procs.stop(role)) finals[role] = *st;
  obs.spin_for(500 * kMs);

  agm::CleanTableReport rep = agm::check_clean_table(g);
  if (!rep.mission_holds) {
    std::string why;
    for (const auto& m : rep.missing) why += (why.empty() ? "" : "; ") + m;
    failures.push_back("the mission does not hold on the final replica: " + why);
  }
  if (rep.plan_status != "achieved")
    failures.push_back("the plan node says '" + rep.plan_status + "'");
  std::string verified = "no plan";
  if (plans.empty()) {
    failures.push_back("the observer saw no plan");
  } else {
    Status v = agm::verify_clean_table_plan(plans.begin()->second);
    verified = v.ok() ? "ok" : v.error().to_string();
    if (!v.ok()) failures.push_back("the first plan does not replay through the guard: " + verified);
  }
  for (const char* mug : {"mug", "mug2"})
    if (grasped[mug] != 1 || released[mug] != 1)
      failures.push_back(std::string(mug) + " grasped " + std::to_string(grasped[mug]) +
                         " and released " + std::to_string(released[mug]) + " times");
  if (max_carrying > 1) failures.push_back("two objects carried at once");
  const std::string digest = g.digest().hex();
  bool equal = finals.size() == 4;
  for (const auto& [role, st] : finals)
    if (st.value("digest", "") != digest) {
      failures.push_back(role + "'s replica differs from the observer's at the end");
      equal = false;
    }
  if (finals.size() != 4) failures.push_back("not every agent reported its final state");
  if (humans) finals["humans"] = *humans;
  for (const auto& [role, st] : finals)
    if (st.value("exit_status", -1) != 0)
      failures.push_back(role + " exited with status " +
                         std::to_string(st.value("exit_status", -1)));
  agm::LatencyProbe pooled;
  for (const auto& [role, st] : finals)
    if (st.contains("humans_latency")) pooled.merge_json(st["humans_latency"]);
  std::printf(
      "\nChecks: mission %s on the final replica; plan '%s' (version %lld, %lld replans), its "
      "first version through the grammar guard: %s; %d changeRoom; mugs grasped/released "
      "%d/%d and %d/%d; human joints reached the others: p50 %.0f us, p99 %.0f us (%llu poses); "
      "replicas %s.\n",
      rep.mission_holds ? "holds" : "does NOT hold", rep.plan_status.c_str(),
      static_cast<long long>(rep.version), static_cast<long long>(rep.replans), verified.c_str(),
      room_changes, grasped["mug"], released["mug"], grasped["mug2"], released["mug2"],
      pooled.percentile_us(0.5), pooled.percentile_us(0.99),
      static_cast<unsigned long long>(pooled.count()),
      (equal ? "all equal (digest " + digest.substr(0, 12) + ")" : std::string("NOT equal"))
          .c_str());
  for (const auto& d : failures) std::printf("  FAILED: %s\n", d.c_str());
  std::printf(failures.empty() ? "The mission holds; the run passed its checks.\n"
                               : "The run FAILED its checks.\n");
  return failures.empty() ? 0 : 1;
}

int run_agm_scenario(const AgmScenarioFlags& f) {
  if (f.mission == agm::kCleanTable) return run_agm_clean_table(f);
  auto log = agents::named_logger("quiver scenario");
  const std::string out = make_out(f.out, "quiver-agm");
  agents::DdsReplicaOptions o;
  o.name = "agm-observer";
  o.observer = true;
  auto created = f.dds.create_agent(o);
  if (!created.ok()) {
    log->error("{}", created.error().to_string());
    return 2;
  }
  agents::DdsReplica& obs = **created;
  graph::Graph& g = obs.graph();
  const std::int64_t t_start = agents::monotonic_ns();
  auto elapsed = [&] { return static_cast<double>(agents::monotonic_ns() - t_start) / 1e9; };
  auto say = [&](const std::string& line) {
    std::printf("[%6.2f s] %s\n", elapsed(), line.c_str());
    std::fflush(stdout);
  };

  // What the observer sees happen (in the order its replica learns it).
  struct InEdge {
    std::string to;
    double x, y;
    std::int64_t stamp, committed;
  };
  std::vector<InEdge> ins;
  int moved_set = 0, moved_cleared = 0, reach_set = 0, noreach_set = 0, grasp_started = 0,
      grasp_paused = 0;
  std::vector<std::int64_t> moved_since;
  std::vector<std::string> failures;
  auto robot_id = [&] { return agm::node_id(g, agm::node::kRobot); };
  g.subscribe([&](const graph::ChangeBatch& b) {
    const NodeId robot = robot_id();
    if (robot.is_null()) return;
    for (const graph::EdgeChange& e : b.edges) {
      const std::string type(e.key.type.str());
      const std::string from = g.name_of(e.key.from), to = g.name_of(e.key.to);
      if (e.key.from != robot) continue;
      const bool made = e.kind == graph::ChangeKind::kCreated,
                 gone = e.kind == graph::ChangeKind::kDeleted;
      // Edges of the world file (the seed) are not the agents' doing: theirs carry what they were
      // based on.
      if (type == agm::edge::kIn && made && g.edge_attr(e.key, "committed_ns")) {
        InEdge in{to, edge_attr_or(g, e.key, "x", 0.0), edge_attr_or(g, e.key, "y", 0.0),
                  edge_attr_or<std::int64_t>(g, e.key, "stamp_ns", 0),
                  edge_attr_or<std::int64_t>(g, e.key, "committed_ns", 0)};
        ins.push_back(in);
        char line[200];
        std::snprintf(line, sizeof line,
                      "changeRoom -> %s at (%.3f, %.3f), committed %.1f ms after that pose",
                      to.c_str(), in.x, in.y, static_cast<double>(in.committed - in.stamp) / 1e6);
        say(line);
      } else if (type == agm::edge::kMoved && (made || gone)) {
        ++(made ? moved_set : moved_cleared);
        if (made) moved_since.push_back(edge_attr_or<std::int64_t>(g, e.key, "since_ns", 0));
        say(std::string("movedInLastSeconds ") + (made ? "set" : "cleared"));
      } else if ((type == agm::edge::kReach || type == agm::edge::kNoReach) && made &&
                 g.edge_attr(e.key, "distance")) {
        ++(type == agm::edge::kReach ? reach_set : noreach_set);
        char line[160];
        std::snprintf(line, sizeof line, "%s %s (FCL distance %.3f m)", type.c_str(), to.c_str(),
                      edge_attr_or(g, e.key, "distance", -1.0));
        say(line);
      } else if (type == agm::edge::kGrasping && (made || gone)) {
        if (made)
          ++grasp_started;
        else if (!g.has_edge(robot, e.key.to, agm::edge::kCarrying))
          ++grasp_paused;
        say("grasp of " + to +
            (made                                                ? " started"
             : g.has_edge(robot, e.key.to, agm::edge::kCarrying) ? " done"
                                                                 : " paused"));
      } else if (type == agm::edge::kCarrying && made) {
        say("the robot carries the " + to);
      }
    }
  });

  std::printf(
      "AGM scenarios over Cyclone DDS (domain %u, loopback): navigation, rooms, grasping and "
      "humans, one process "
      "each, no executive.\nLogs: %s/logs/\n\n",
      f.dds.domain, out.c_str());
  AgmProcesses procs(f.dds, out);
  if (!procs.start("navigation", {"--measure-humans", "--quiet-when-done"}) ||
      !procs.start("rooms", {"--measure-humans"}) ||
      !procs.start("grasping", {"--measure-humans"}) || !procs.start("humans", {})) {
    log->error("cannot start {} run ROLE", self_executable());
    return 2;
  }

  // The platform's truth, replayed from what the navigation agent wrote (start and release).
  agm::Platform truth(agm::default_route(), agm::default_start());
  const std::int64_t deadline = t_start + static_cast<std::int64_t>(f.timeout_s * 1e9);
  bool done = false;
  bool killed = false, restarted = false;
  while (agents::monotonic_ns() < deadline && !done) {
    obs.spin_once(20 * kMs);
    if (!f.kill.empty() && !killed && elapsed() >= f.kill_at_s) {
      const int pid = procs.kill(f.kill);
      say("*** kill -9 " + f.kill + " (pid " + std::to_string(pid) + ")");
      killed = true;
    }
    if (killed && !restarted && elapsed() >= f.kill_at_s + f.restart_after_s) {
      if (!procs.restart(f.kill)) failures.push_back("cannot restart " + f.kill);
      say("*** " + f.kill +
          " restarted (an empty replica: it continues from what the graph holds)");
      restarted = true;
    }
    const NodeId robot = robot_id();
    if (robot.is_null()) continue;
    if (auto t0 = g.get<std::int64_t>(robot, agm::attr::kRouteT0); t0.ok()) truth.start(*t0);
    if (auto rel = g.get<std::int64_t>(robot, agm::attr::kRouteRelease);
        rel.ok() && !truth.released_at()) {
      if (!truth.release(*rel))
        failures.push_back("the platform was released when it was not waiting");
    }
    const std::int64_t now = agents::monotonic_ns();
    done = truth.started() && truth.released_at() && truth.finished(now) &&
           now > *truth.end_time() + 2 * kSec && !g.has_edge(robot, robot, agm::edge::kMoved);
  }
  if (!done)
    failures.push_back("the scenario did not end within " + std::to_string(f.timeout_s) + " s");

  // Stop: the tracker first, then (once its last poses are everywhere) the others.
  auto humans = procs.stop("humans");
  obs.spin_for(500 * kMs);
  std::map<std::string, json> finals;
  for (const char* role : {"navigation", "rooms", "grasping"})
    if (auto st = procs.stop(role)) finals[role] = *st;
  obs.spin_for(500 * kMs);

  // Checks.
  const NodeId robot = robot_id(), mug = agm::node_id(g, "mug");
  auto room = agm::room_of(g, robot);
  const std::string final_room = room ? g.name_of(*room) : "";
  if (final_room != "kitchen")
    failures.push_back("the robot ends in '" + final_room + "', not in the kitchen");
  if (!g.has_edge(robot, mug, agm::edge::kCarrying))
    failures.push_back("the robot does not carry the mug");
  if (auto mr = agm::room_of(g, mug); !mr || g.name_of(*mr) != "kitchen")
    failures.push_back("the mug is not in the kitchen");
  if (g.has_edge(robot, robot, agm::edge::kMoved))
    failures.push_back("movedInLastSeconds still set on a parked robot");
  // changeRoom: exactly the platform's crossings, each at the first or second pose past it.
  std::vector<std::string> expected;
  if (truth.started() && truth.end_time()) {
    std::string prev = "kitchen";
    for (std::int64_t t = truth.t0(); t <= *truth.end_time(); t += kMs) {
      auto p = truth.pose(t);
      auto in = agm::room_at(g, p.x, p.y);
      if (in && g.name_of(*in) != prev) expected.push_back(prev = g.name_of(*in));
    }
  }
  std::string prev = "kitchen";
  std::vector<std::string> got;
  for (const InEdge& in : ins) {
    got.push_back(in.to);
    auto to = g.find_node(in.to);
    auto limits = to ? agm::room_limits(g, *to)
                     : Result<agm::Polygon>(make_error(ErrorCode::kNotFound, in.to));
    if (!limits.ok() || !limits->contains(in.x, in.y))
      failures.push_back("changeRoom -> " + in.to + " on a pose outside it");
    const auto before = truth.pose(in.stamp - 2 * (kSec / 30));
    auto was = agm::room_at(g, before.x, before.y);
    if (!was || g.name_of(*was) != prev)
      failures.push_back("changeRoom " + prev + " -> " + in.to + " late (not at the crossing)");
    if (static_cast<double>(in.committed - in.stamp) > f.crossing_lag_ms * 1e6)
      failures.push_back("changeRoom -> " + in.to + " committed " +
                         std::to_string((in.committed - in.stamp) / kMs) + " ms after its pose");
    prev = in.to;
  }
  if (got != expected)
    failures.push_back("changeRoom issued " + std::to_string(got.size()) +
                       " times, the platform crossed " + std::to_string(expected.size()) +
                       " room limits");
  // movedInLastSeconds: set once per episode of driving (drives closer than the window merge).
  int episodes = 0;
  std::int64_t last_end = -1;
  std::vector<std::int64_t> episode_begins;
  for (auto [b, e] : truth.drives()) {
    if (last_end < 0 || b - last_end >= kSec) {
      ++episodes;
      episode_begins.push_back(b);
    }
    last_end = e;
  }
  if (moved_set != episodes || moved_cleared != episodes)
    failures.push_back("movedInLastSeconds set " + std::to_string(moved_set) + " and cleared " +
                       std::to_string(moved_cleared) + " times for " + std::to_string(episodes) +
                       " episodes of driving");
  for (std::size_t i = 0; i < moved_since.size() && i < episode_begins.size(); ++i)
    if (moved_since[i] < episode_begins[i] || moved_since[i] - episode_begins[i] > 100 * kMs)
      failures.push_back("movedInLastSeconds set " +
                         std::to_string((moved_since[i] - episode_begins[i]) / kMs) +
                         " ms after the platform started driving");
  // reach: once, below the threshold (FCL's distance and the true one), never back.
  if (reach_set != 1 || noreach_set != 0)
    failures.push_back("reach set " + std::to_string(reach_set) + " and noReach " +
                       std::to_string(noreach_set) + " times (expected once and never)");
  if (const graph::EdgeKey k{robot, mug, graph::Symbol(agm::edge::kReach)};
      g.has_edge(robot, mug, agm::edge::kReach)) {
    const double d = edge_attr_or(g, k, "distance", 1.0);
    const auto p = truth.pose(edge_attr_or<std::int64_t>(g, k, "stamp_ns", 0));
    const double gx = p.x + 0.35, true_d = std::max(0.0, std::hypot(gx - 8.70, p.y - 2.0) - 0.08);
    if (d >= 0.10 || true_d >= 0.11)
      failures.push_back("reach set at FCL distance " + std::to_string(d) + " m (true " +
                         std::to_string(true_d) + " m)");
  }
  // No grasp while moving; the nudge paused it.
  if (const graph::EdgeKey k{robot, mug, graph::Symbol(agm::edge::kCarrying)};
      g.has_edge(robot, mug, agm::edge::kCarrying)) {
    const auto began = edge_attr_or<std::int64_t>(g, k, "started_ns", 0),
               ended = edge_attr_or<std::int64_t>(g, k, "finished_ns", 0);
    for (auto [b, e] : truth.drives())
      if (e > began && b < ended - static_cast<std::int64_t>(f.motion_allowance_ms * 1e6))
        failures.push_back("grasped though the platform drove during the grasp");
  }
  if (grasp_paused < 1) failures.push_back("the nudge mid-grasp did not pause the grasp");
  // All replicas equal.
  const std::string digest = g.digest().hex();
  bool equal = finals.size() == 3;
  for (const auto& [role, st] : finals)
    if (st.value("digest", "") != digest) {
      failures.push_back(role + "'s replica differs from the observer's at the end");
      equal = false;
    }
  if (finals.size() != 3) failures.push_back("not every agent reported its final state");
  if (humans) finals["humans"] = *humans;
  for (const auto& [role, st] : finals)
    if (st.value("exit_status", -1) != 0)
      failures.push_back(role + " exited with status " +
                         std::to_string(st.value("exit_status", -1)));

  // Human tracking, as the other agents saw it.
  agm::LatencyProbe pooled;
  std::printf(
      "\nHuman tracking (2 people x 15 joints x 30 Hz, one transaction per person and frame): ");
  if (humans) {
    const double secs = static_cast<double>((*humans)["last_ns"].get<std::int64_t>() -
                                            (*humans)["first_ns"].get<std::int64_t>()) /
                        1e9;
    std::printf("%.0f RT updates/s\n",
                secs > 0 ? (*humans)["rt_updates"].get<double>() / secs : 0.0);
  } else {
    std::printf("no status\n");
  }
  for (const auto& [role, st] : finals)
    if (st.contains("humans_latency")) {
      const json& h = st["humans_latency"];
      pooled.merge_json(h);
      std::printf("  reaching %-10s p50 %7.0f us  p99 %7.0f us  max %7.0f us  (%llu poses)\n",
                  role.c_str(), h["p50_us"].get<double>(), h["p99_us"].get<double>(),
                  h["max_us"].get<double>(),
                  static_cast<unsigned long long>(h["count"].get<std::uint64_t>()));
    }
  if (pooled.count() == 0) failures.push_back("no human joint pose reached the other agents");
  std::printf(
      "\nChecks: robot ends in %s carrying the mug; %zu changeRoom for %zu crossings, each at the "
      "crossing; "
      "movedInLastSeconds %d/%d for %d drives; reach set %d time(s) below 0.10 m; grasp paused %d "
      "time(s) while "
      "driving; replicas %s.\n",
      final_room.c_str(), got.size(), expected.size(), moved_set, moved_cleared, episodes,
      reach_set, grasp_paused,
      (equal ? "all equal (digest " + digest.substr(0, 12) + ")" : std::string("NOT equal"))
          .c_str());
  for (const auto& d : failures) std::printf("  FAILED: %s\n", d.c_str());
  std::printf(failures.empty() ? "The scenario's expected facts hold.\n"
                               : "The run FAILED its checks.\n");
  return failures.empty() ? 0 : 1;
}

// ------------------------------------------------------------------ quiver bench humans

struct HumansBenchFlags {
  DdsFlags dds;
  std::string out;
  double seconds = 10;
  double max_p99_ms = 10;
  bool no_planner = false;
};

int run_humans_bench(const HumansBenchFlags& f) {
  auto log = agents::named_logger("quiver bench humans");
  const std::string out = make_out(f.out, "quiver-bench-humans");
  AgmProcesses procs(f.dds, out);
  std::vector<std::string> others = {"navigation", "rooms", "grasping"};
  if (!f.no_planner) others.push_back(agm::kPlannerRole);
  // With the planner (the default): the clean-the-table mission, the planner agent planning
  // and tracking the plan, navigation and grasping following it.
  std::vector<std::string> mission;
  if (!f.no_planner) mission = {"--mission", agm::kCleanTable};
  auto with = [&](std::vector<std::string> a) {
    a.insert(a.end(), mission.begin(), mission.end());
    return a;
  };
  for (const auto& r : others)
    if (!procs.start(r, with({"--measure-humans"}))) {
      log->error("cannot start {} run {}", self_executable(), r);
      return 2;
    }
  // The others join and warm up (their probes start 0.5 s after their setup) before tracking.
  ::usleep(3'000'000);
  if (!procs.start("humans", with({}))) return 2;
  ::usleep(static_cast<useconds_t>((1.0 + f.seconds) * 1e6));  // 1 s: the tracker's own join wait
  auto humans = procs.stop("humans");
  ::usleep(300'000);
  agm::LatencyProbe pooled;
  json per_agent = json::object();
  std::uint64_t deliveries = 0;
  double delivery_secs = 0;
  std::map<std::string, int> exit_statuses;
  json planner_status;
  for (const auto& r : others) {
    auto st = procs.stop(r);
    if (r == agm::kPlannerRole && st)
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
      delivery_secs =
          std::max(delivery_secs, static_cast<double>(h["last_ns"].get<std::int64_t>() -
                                                      h["first_ns"].get<std::int64_t>()) /
                                      1e9);
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
    const double secs = static_cast<double>((*humans)["last_ns"].get<std::int64_t>() -
                                            (*humans)["first_ns"].get<std::int64_t>()) /
                        1e9;
    res["seconds"] = round_to(secs, 2);
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
  res["p99_limit_ms"] = f.max_p99_ms;
  bool clean = humans && humans->value("exit_status", -1) == 0;
  for (const auto& r : others) clean = clean && exit_statuses[r] == 0;
  if (!f.no_planner) {
    res["planner"] = planner_status;
    res["mission"] = agm::kCleanTable;
  }
  res["agents_exited_cleanly"] = clean;
  const bool ok = clean && deliveries > 0 && pooled.percentile_us(0.99) <= f.max_p99_ms * 1e3;
  res["ok"] = ok;
  std::cout << res.dump() << std::endl;
  return ok ? 0 : 1;
}

}  // namespace

void add_agm_commands(CLI::App& app) {
  auto sf = std::make_shared<AgmScenarioFlags>();
  sf->dds.domain = 48;
  CLI::App* scenario = app.get_subcommand("scenario");
  auto* a = scenario->add_subcommand("agm",
                                     "The AGM scenarios (seed 001): navigation, robot-in-room, "
                                     "grasping, human tracking; one process each");
  sf->dds.add_to(a);
  a->add_option("--out", sf->out, "logs go to OUT/logs (default: a new /tmp/quiver-agm-*)");
  a->add_option("--timeout", sf->timeout_s, "give up after this many seconds")
      ->check(CLI::Range(1.0, 86400.0))
      ->capture_default_str();
  a->add_option("--crossing-lag-ms", sf->crossing_lag_ms,
                "check: changeRoom committed within this of the pose past the limit")
      ->check(CLI::Range(1.0, 10000.0))
      ->capture_default_str();
  a->add_option("--motion-allowance-ms", sf->motion_allowance_ms,
                "check: a grasp ends within this of the platform moving")
      ->check(CLI::Range(1.0, 10000.0))
      ->capture_default_str();
  a->add_option("--kill", sf->kill,
                "kill -9 this agent (navigation, rooms, grasping, humans) mid-run and restart it")
      ->check(CLI::IsMember(agm::role_names()));
  a->add_option("--mission", sf->mission,
                "clean-table: the planner agent runs too (a fifth process) and navigation and "
                "grasping follow its plan: both mugs from the table to the kitchen")
      ->check(CLI::IsMember({"", "clean-table"}));
  a->add_option("--kill-at", sf->kill_at_s, "... this many seconds after the start")
      ->check(CLI::Range(0.0, 3600.0))
      ->capture_default_str();
  a->add_option("--restart-after", sf->restart_after_s,
                "... and restart it this many seconds later")
      ->check(CLI::Range(0.0, 600.0))
      ->capture_default_str();
  a->callback([sf] { set_exit_code(run_agm_scenario(*sf)); });

  auto bf = std::make_shared<HumansBenchFlags>();
  bf->dds.domain = 49;
  CLI::App* bench = app.get_subcommand("bench");
  auto* h = bench->add_subcommand(
      "humans",
      "Human tracking (2 people x 15 joints x 30 Hz) reaching the navigation, rooms and grasping "
      "agents while they work: latency p50/p99/max, rate");
  bf->dds.add_to(h);
  h->add_option("--seconds", bf->seconds, "how long the tracker runs")
      ->check(CLI::Range(1.0, 3600.0))
      ->capture_default_str();
  h->add_option("--max-p99-ms", bf->max_p99_ms, "exit 1 when the p99 latency exceeds this")
      ->check(CLI::Range(0.01, 10000.0))
      ->capture_default_str();
  h->add_flag("--no-planner", bf->no_planner,
              "without the planner agent: the fixed route (default: the clean-the-table mission, "
              "the planner agent planning and tracking, navigation and grasping following it)");
  h->add_option("--out", bf->out,
                "logs go to OUT/logs (default: a new /tmp/quiver-bench-humans-*)");
  h->callback([bf] { set_exit_code(run_humans_bench(*bf)); });
}

}  // namespace quiver::tools
