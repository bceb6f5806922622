// The fixed route over DDS (`quiver scenario agm`): navigation, rooms, grasping and humans, one
// process each, watched from the observer's replica and checked at the end.
#include <cstdio>

#include "observed_run.h"
#include "quiver/agents/apps/agm/agm_checks.h"
#include "quiver/agents/apps/agm/agm_roles.h"
#include "quiver/agents/apps/agm/agm_schema.h"
#include "quiver/agents/apps/agm/latency_probe.h"
#include "quiver/agents/runtime/process/logging.h"

namespace quiver::agents::inline apps::agm::internal {
namespace {

using graph::NodeId;
using json = nlohmann::json;

template <class T>
T edge_attr_or(const graph::Graph& g, const graph::EdgeKey& k, const char* name, T fallback) {
  const graph::Value* v = g.edge_attr(k, name);
  const T* p = v ? v->get_if<T>() : nullptr;
  return p ? *p : fallback;
}

// What the observer sees the agents do (in the order its replica learns it). Edges of the world
// file (the seed) are not the agents' doing: theirs carry what they were based on.
struct Seen {
  std::vector<RoomChange> changes;  ///< `from`: the room before, from the kitchen on
  std::vector<GraspEvent> reach;    ///< kReach, kNoReach
  int moved_set = 0, moved_cleared = 0, grasp_paused = 0;
  std::vector<std::int64_t> moved_since;

  void on_edge(ObservedRun& run, const graph::Graph& g, NodeId robot, const graph::EdgeChange& e) {
    const std::string type(e.key.type.str()), to = g.name_of(e.key.to);
    const bool made = e.kind == graph::ChangeKind::kCreated,
               gone = e.kind == graph::ChangeKind::kDeleted;
    if (type == edge::kIn && made && g.edge_attr(e.key, "committed_ns")) {
      RoomChange c{changes.empty() ? "kitchen" : changes.back().to,
                   to,
                   edge_attr_or(g, e.key, "x", 0.0),
                   edge_attr_or(g, e.key, "y", 0.0),
                   edge_attr_or<std::int64_t>(g, e.key, "stamp_ns", 0),
                   edge_attr_or<std::int64_t>(g, e.key, "committed_ns", 0)};
      changes.push_back(c);
      char line[200];
      std::snprintf(line, sizeof line,
                    "changeRoom -> %s at (%.3f, %.3f), committed %.1f ms after that pose",
                    to.c_str(), c.x, c.y, static_cast<double>(c.committed_ns - c.stamp_ns) / 1e6);
      run.say(line);
    } else if (type == edge::kMoved && (made || gone)) {
      ++(made ? moved_set : moved_cleared);
      if (made) moved_since.push_back(edge_attr_or<std::int64_t>(g, e.key, "since_ns", 0));
      run.say(std::string("movedInLastSeconds ") + (made ? "set" : "cleared"));
    } else if ((type == edge::kReach || type == edge::kNoReach) && made &&
               g.edge_attr(e.key, "distance")) {
      GraspEvent r;
      r.kind = type == edge::kReach ? GraspEvent::Kind::kReach : GraspEvent::Kind::kNoReach;
      r.object = to;
      r.distance = edge_attr_or(g, e.key, "distance", -1.0);
      r.stamp_ns = edge_attr_or<std::int64_t>(g, e.key, "stamp_ns", 0);
      r.t_ns = monotonic_ns();
      reach.push_back(r);
      char line[160];
      std::snprintf(line, sizeof line, "%s %s (FCL distance %.3f m)", type.c_str(), to.c_str(),
                    r.distance);
      run.say(line);
    } else if (type == edge::kGrasping && (made || gone)) {
      const bool carried = g.has_edge(robot, e.key.to, edge::kCarrying);
      if (gone && !carried) ++grasp_paused;
      run.say("grasp of " + to + (made ? " started" : carried ? " done" : " paused"));
    } else if (type == edge::kCarrying && made) {
      run.say("the robot carries the " + to);
    }
  }
};

// movedInLastSeconds: set once per episode of driving (drives closer than the window merge),
// within 100 ms of the platform starting.
std::vector<std::string> moved_failures(const Platform& truth, const Seen& seen, int& episodes) {
  std::vector<std::string> f;
  std::int64_t last_end = -1;
  std::vector<std::int64_t> begins;
  for (auto [b, e] : truth.drives()) {
    if (last_end < 0 || b - last_end >= kSec) begins.push_back(b);
    last_end = e;
  }
  episodes = static_cast<int>(begins.size());
  if (seen.moved_set != episodes || seen.moved_cleared != episodes)
    f.push_back("movedInLastSeconds set " + std::to_string(seen.moved_set) + " and cleared " +
                std::to_string(seen.moved_cleared) + " times for " + std::to_string(episodes) +
                " episodes of driving");
  for (std::size_t i = 0; i < seen.moved_since.size() && i < begins.size(); ++i)
    if (seen.moved_since[i] < begins[i] || seen.moved_since[i] - begins[i] > 100 * kMs)
      f.push_back("movedInLastSeconds set " +
                  std::to_string((seen.moved_since[i] - begins[i]) / kMs) +
                  " ms after the platform started driving");
  return f;
}

// The grasp of the mug as the carrying edge records it: its last uninterrupted run.
std::vector<GraspEvent> grasp_of_mug(const graph::Graph& g) {
  const NodeId robot = node_id(g, node::kRobot), mug = node_id(g, "mug");
  if (!g.has_edge(robot, mug, edge::kCarrying)) return {};
  const graph::EdgeKey k{robot, mug, graph::Symbol(edge::kCarrying)};
  GraspEvent started, grasped;
  started.kind = GraspEvent::Kind::kStarted;
  grasped.kind = GraspEvent::Kind::kGrasped;
  started.object = grasped.object = "mug";
  started.t_ns = edge_attr_or<std::int64_t>(g, k, "started_ns", 0);
  grasped.t_ns = edge_attr_or<std::int64_t>(g, k, "finished_ns", 0);
  return {started, grasped};
}

}  // namespace

int run_route(const AgmDdsRun& r) {
  auto opened = ObservedRun::open(r, "quiver-agm", world_json());
  if (!opened) return 2;
  ObservedRun& run = *opened;
  graph::Graph& g = run.graph();
  Seen seen;
  run.watch([&](NodeId robot, const graph::EdgeChange& e) { seen.on_edge(run, g, robot, e); });
  if (!run.start("AGM scenarios", "navigation, rooms, grasping and humans",
                 {{"navigation", {"--measure-humans", "--quiet-when-done"}},
                  {"rooms", {"--measure-humans"}},
                  {"grasping", {"--measure-humans"}},
                  {"humans", {}}}))
    return 2;
  AgmProcesses& procs = run.processes();
  std::vector<std::string> failures;

  // The platform's truth, replayed from what the navigation agent wrote (start and release).
  Platform truth(default_route(), default_start());
  const std::int64_t deadline = run.started_ns() + static_cast<std::int64_t>(r.timeout_s * 1e9);
  bool done = false, killed = false, restarted = false;
  while (monotonic_ns() < deadline && !done) {
    run.replica().spin_once(20 * kMs);
    if (!r.kill.empty() && !killed && run.elapsed() >= r.kill_at_s) {
      const int pid = procs.kill(r.kill);
      run.say("*** kill -9 " + r.kill + " (pid " + std::to_string(pid) + ")");
      killed = true;
    }
    if (killed && !restarted && run.elapsed() >= r.kill_at_s + r.restart_after_s) {
      if (!procs.restart(r.kill)) failures.push_back("cannot restart " + r.kill);
      run.say("*** " + r.kill +
              " restarted (an empty replica: it continues from what the graph holds)");
      restarted = true;
    }
    const NodeId robot = node_id(g, node::kRobot);
    if (robot.is_null()) continue;
    if (auto t0 = g.get<std::int64_t>(robot, attr::kRouteT0); t0.ok()) truth.start(*t0);
    if (auto rel = g.get<std::int64_t>(robot, attr::kRouteRelease);
        rel.ok() && !truth.released_at()) {
      if (!truth.release(*rel))
        failures.push_back("the platform was released when it was not waiting");
    }
    const std::int64_t now = monotonic_ns();
    done = truth.started() && truth.released_at() && truth.finished(now) &&
           now > *truth.end_time() + 2 * kSec && !g.has_edge(robot, robot, edge::kMoved);
  }
  if (!done)
    failures.push_back("the scenario did not end within " + std::to_string(r.timeout_s) + " s");

  std::optional<json> humans;
  std::map<std::string, json> finals = run.stop({"navigation", "rooms", "grasping"}, humans);

  // Checks: those of the simulator on what the observer saw, and the processes' own.
  append(failures, end_state_failures(g, ""));
  const std::vector<Crossing> expected = truth.started() && truth.end_time()
                                             ? crossings(truth, g, *truth.end_time())
                                             : std::vector<Crossing>{};
  const NavigationOptions nav;
  const auto frame = static_cast<std::int64_t>(1e9 / nav.rate_hz);
  append(failures, room_change_failures(g, truth, seen.changes, true, r.crossing_lag_ms, frame));
  append(failures, crossing_count_failures(seen.changes, expected, true));
  int episodes = 0;
  append(failures, moved_failures(truth, seen, episodes));
  append(failures, reach_failures(seen.reach, truth, GraspingOptions{}.reach_on_m, true));
  const auto allowance = static_cast<std::int64_t>(r.motion_allowance_ms * 1e6);
  append(failures, grasp_motion_failures(grasp_of_mug(g), truth, allowance, nav.moved_window_ns));
  if (seen.grasp_paused < 1) failures.push_back("the nudge mid-grasp did not pause the grasp");
  const std::string digest = g.digest().hex();
  bool equal = false;
  append(failures, final_status_failures(finals, digest, 3, humans, equal));

  // Human tracking, as the other agents saw it.
  LatencyProbe pooled;
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
  int reach_set = 0;
  for (const GraspEvent& e : seen.reach) reach_set += e.kind == GraspEvent::Kind::kReach;
  auto room = room_of(g, node_id(g, node::kRobot));
  std::printf(
      "\nChecks: robot ends in %s carrying the mug; %zu changeRoom for %zu crossings, each at the "
      "crossing; "
      "movedInLastSeconds %d/%d for %d drives; reach set %d time(s) below 0.10 m; grasp paused %d "
      "time(s) while "
      "driving; replicas %s.\n",
      room ? g.name_of(*room).c_str() : "", seen.changes.size(), expected.size(), seen.moved_set,
      seen.moved_cleared, episodes, reach_set, seen.grasp_paused,
      (equal ? "all equal (digest " + digest.substr(0, 12) + ")" : std::string("NOT equal"))
          .c_str());
  return ObservedRun::verdict(failures, "The scenario's expected facts hold.");
}

}  // namespace quiver::agents::inline apps::agm::internal
