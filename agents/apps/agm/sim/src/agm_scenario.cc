#include "quiver/agents/apps/agm/sim/agm_scenario.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "quiver/agents/apps/agm/agm_roles.h"
#include "quiver/agents/apps/agm/agm_schema.h"
#include "quiver/sim/agent_host.h"
#include "quiver/sim/fault_generator.h"
#include "quiver/sim/fault_model.h"
#include "quiver/sim/simulator.h"

namespace quiver::agents::inline apps::agm {

using namespace quiver::sim;  // the simulator this scenario runs on

using graph::NodeId;
using nlohmann::json;

namespace {

constexpr std::int64_t kMs = 1'000'000;
constexpr std::int64_t kSec = 1'000'000'000;

// The scenario's geometry, as the world file states it (the checks compute independently of the
// agents' FCL scene): the gripper, a sphere at X_RG from the robot; the mug, an upright cylinder.
constexpr double kGripperX = 0.35, kGripperRadius = 0.04;
constexpr double kMugX = 8.70, kMugY = 2.0, kMugRadius = 0.04;

// Closed-form distance between the gripper and the mug (same height, so horizontal).
double gripper_mug_distance(const agm::Pose2& p) {
  const double gx = p.x + kGripperX * std::cos(p.yaw), gy = p.y + kGripperX * std::sin(p.yaw);
  return std::max(0.0, std::hypot(gx - kMugX, gy - kMugY) - kMugRadius - kGripperRadius);
}

std::string fmt_s(std::int64_t t) {
  std::ostringstream o;
  o.precision(3);
  o << std::fixed << static_cast<double>(t) / 1e9 << " s";
  return o.str();
}

}  // namespace

json AgmResult::to_json() const {
  return {{"name", name},
          {"seed", seed},
          {"passed", passed},
          {"failures", failures},
          {"converged", converged},
          {"final_room", final_room},
          {"room_changes", room_changes},
          {"expected_room_changes", expected_room_changes},
          {"reach_changes", reach_changes},
          {"pauses", pauses},
          {"grasps", grasps},
          {"grasped_s", grasped_s},
          {"finished_s", finished_s},
          {"kills", kills},
          {"partitions", partitions},
          {"rejected", rejected},
          {"human_deliveries", human_deliveries},
          {"human_latency_p99_ms", human_latency_p99_ms},
          {"mission_holds", mission_holds},
          {"plan_status", plan_status},
          {"plan_verified", plan_verified},
          {"plan_steps", plan_steps},
          {"plan_version", plan_version},
          {"replans", replans},
          {"releases", releases}};
}

namespace {

Error bad(const std::string& source, const std::string& pointer, const std::string& what) {
  return Error{ErrorCode::kInvalidArgument, source + ":" + pointer + ": " + what};
}

}  // namespace

Result<AgmScenario> AgmScenario::parse(const json& j, const std::string& source) {
  AgmScenario s;
  if (!j.is_object()) return bad(source, "/", "a scenario is a JSON object");
  static const char* kKeys[] = {"name",        "faults",  "checks",  "humans",    "humans_hz",
                                "reach_off_m", "limit_s", "mission", "put_back_s"};
  for (auto it = j.begin(); it != j.end(); ++it)
    if (std::none_of(std::begin(kKeys), std::end(kKeys),
                     [&](const char* k) { return it.key() == k; }))
      return bad(source, "/" + it.key(), "unknown key");
  if (j.contains("name")) {
    if (!j["name"].is_string()) return bad(source, "/name", "expected a string");
    s.name = j["name"].get<std::string>();
  }
  auto agent = [&](const json& v, const std::string& where) -> Result<std::string> {
    if (!v.is_string() || !agm::is_role_or_planner(v.get<std::string>()))
      return bad(source, where, "not an agent (navigation, rooms, grasping, humans, agm-planner)");
    return v.get<std::string>();
  };
  if (j.contains("faults")) {
    if (!j["faults"].is_array()) return bad(source, "/faults", "expected an array");
    for (std::size_t i = 0; i < j["faults"].size(); ++i) {
      const json& f = j["faults"][i];
      const std::string where = "/faults/" + std::to_string(i);
      if (!f.is_object() || !f.contains("at_s") || !f["at_s"].is_number() ||
          f["at_s"].get<double>() < 0)
        return bad(source, where,
                   "expected {\"at_s\": T >= 0, and one of partition, heal, kill, restart, loss}");
      FaultEvent e;
      e.at_s = f["at_s"].get<double>();
      if (f.contains("partition")) {
        e.kind = FaultEvent::Kind::kPartition;
        const json& gs = f["partition"];
        if (!gs.is_array() || gs.empty())
          return bad(source, where + "/partition", "expected groups of agent names");
        for (std::size_t g = 0; g < gs.size(); ++g) {
          if (!gs[g].is_array())
            return bad(source, where + "/partition/" + std::to_string(g),
                       "expected an array of names");
          std::vector<std::string> group;
          for (std::size_t k = 0; k < gs[g].size(); ++k) {
            auto a = agent(gs[g][k],
                           where + "/partition/" + std::to_string(g) + "/" + std::to_string(k));
            if (!a.ok()) return a.error();
            group.push_back(*a);
          }
          e.groups.push_back(group);
        }
      } else if (f.contains("heal")) {
        e.kind = FaultEvent::Kind::kHeal;
      } else if (f.contains("kill") || f.contains("restart")) {
        const bool kill = f.contains("kill");
        e.kind = kill ? FaultEvent::Kind::kKill : FaultEvent::Kind::kRestart;
        auto a = agent(f[kill ? "kill" : "restart"], where + (kill ? "/kill" : "/restart"));
        if (!a.ok()) return a.error();
        e.agent = *a;
      } else if (f.contains("loss")) {
        e.kind = FaultEvent::Kind::kLoss;
        if (!f["loss"].is_number() || f["loss"].get<double>() < 0 || f["loss"].get<double>() > 0.9)
          return bad(source, where + "/loss", "expected a probability in [0, 0.9]");
        e.loss = f["loss"].get<double>();
      } else {
        return bad(source, where, "no fault (partition, heal, kill, restart or loss)");
      }
      s.faults.push_back(e);
    }
  }
  if (j.contains("checks")) {
    const json& c = j["checks"];
    if (!c.is_object()) return bad(source, "/checks", "expected an object");
    for (auto [k, out] : {std::pair{"exact_crossings", &s.checks.exact_crossings},
                          std::pair{"expect_pause", &s.checks.expect_pause}}) {
      if (!c.contains(k)) continue;
      if (!c[k].is_boolean())
        return bad(source, std::string("/checks/") + k, "expected true or false");
      *out = c[k].get<bool>();
    }
    for (auto [k, out] : {std::pair{"crossing_lag_ms", &s.checks.crossing_lag_ms},
                          std::pair{"motion_allowance_ms", &s.checks.motion_allowance_ms}}) {
      if (!c.contains(k)) continue;
      if (!c[k].is_number() || c[k].get<double>() <= 0 || c[k].get<double>() > 60'000)
        return bad(source, std::string("/checks/") + k, "expected milliseconds in (0, 60000]");
      *out = c[k].get<double>();
    }
  }
  if (j.contains("mission")) {
    if (!j["mission"].is_string() ||
        (j["mission"] != "" && j["mission"] != std::string(agm::kCleanTable)))
      return bad(source, "/mission", "expected \"\" or \"clean-table\"");
    s.mission = j["mission"].get<std::string>();
  }
  if (j.contains("humans")) {
    if (!j["humans"].is_boolean()) return bad(source, "/humans", "expected true or false");
    s.humans = j["humans"].get<bool>();
  }
  for (auto [k, out, lo, hi] : {std::tuple{"humans_hz", &s.humans_hz, 1.0, 200.0},
                                std::tuple{"reach_off_m", &s.reach_off_m, 0.10, 1.0},
                                std::tuple{"limit_s", &s.limit_s, 45.0, 86'400.0},
                                std::tuple{"put_back_s", &s.put_back_s, 0.0, 86'400.0}}) {
    if (!j.contains(k)) continue;
    if (!j[k].is_number() || j[k].get<double>() < lo || j[k].get<double>() > hi)
      return bad(source, std::string("/") + k,
                 "expected a number in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    *out = j[k].get<double>();
  }
  return s;
}

Result<AgmScenario> AgmScenario::load(const std::string& path) {
  std::ifstream in(path);
  if (!in) return Error{ErrorCode::kIo, path + ": cannot open the scenario file"};
  try {
    return parse(json::parse(in), path);
  } catch (const json::parse_error& e) {
    return Error{ErrorCode::kInvalidArgument, path + ": not JSON: " + e.what()};
  }
}

AgmScenario AgmScenario::random_faults(std::uint64_t seed) { return random_faults(seed, ""); }

AgmScenario AgmScenario::random_faults(std::uint64_t seed, const std::string& mission) {
  Rng rng(seed ^ 0xa6e5ce7a110ULL);
  AgmScenario s;
  s.name = mission.empty() ? "agm-faults" : mission + "-faults";
  s.mission = mission;
  // Under partitions and loss the agents still decide right from what their replicas hold; what
  // they cannot do is see a crossing or a start of motion they are cut off from.
  s.checks.exact_crossings = false;
  s.checks.expect_pause = false;
  s.checks.motion_allowance_ms =
      500;  // the grasping agent's freshness bound (300 ms), ticks, retries
  std::vector<std::string> roles = agm::role_names();
  if (!mission.empty()) roles.push_back(agm::kPlannerRole);
  sim::FaultMix mix;  // loss up to 20%, up to two partitions and two kill -9, all in the first 35 s
  mix.agents = roles;
  mix.killable = roles;
  s.faults = sim::random_faults(rng, mix);
  return s;
}

AgmResult run_agm_scenario(const AgmScenario& s, std::uint64_t seed,
                           std::function<void(std::int64_t, const std::string&)> log) {
  if (s.mission == agm::kCleanTable) return run_agm_clean_table(s, seed, log);
  AgmResult r;
  r.name = s.name;
  r.seed = seed;
  auto fail = [&](const std::string& f) {
    if (r.failures.size() < 20) r.failures.push_back(f);
  };

  // Devices and records that outlive an agent's incarnation: the platform (the robot keeps
  // driving when its navigation agent dies) and what the agents reported doing.
  auto platform = std::make_shared<agm::Platform>(agm::default_route(), agm::default_start());
  std::vector<agm::RoomChange> changes;
  std::vector<agm::GraspEvent> grasp_events;
  agm::AgmRoleOptions ro;
  ro.platform = platform;
  ro.navigation.quiet_when_done = true;
  ro.rooms.on_change = [&](const agm::RoomChange& c) { changes.push_back(c); };
  ro.grasping.on_event = [&](const agm::GraspEvent& e) { grasp_events.push_back(e); };
  ro.humans.rate_hz = s.humans_hz;
  ro.grasping.reach_off_m = s.reach_off_m;
  ro.measure_humans = s.humans;

  std::vector<SimAgentSpec> specs;
  for (const std::string& role : agm::role_names()) {
    if (role == "humans" && !s.humans) continue;
    specs.push_back({role, [&ro, role]() -> std::unique_ptr<agents::Agent> {
                       auto a = agm::make_role(role, ro);
                       return a.ok() ? std::move(*a) : nullptr;
                     }});
  }
  AgentHostOptions ho;
  ho.seed = seed;
  ho.replicator = SimConfig::default_replicator();
  ho.locks.lease_ns = kSec;
  ho.world_json = std::string(agm::world_json());
  ho.log = log;
  AgentHost host(std::move(specs), ho);
  if (Status st = host.start(); !st.ok()) {
    fail(st.error().to_string());
    return r;
  }
  std::map<int, std::int64_t> started_at;
  host.on_agent_started([&](int i) { started_at[i] = host.now(); });
  sim::FaultCounts counts;
  schedule_faults(host, s.faults, log, counts);

  const int nav = host.index("navigation"), grasping = host.index("grasping");
  const std::int64_t allowance = static_cast<std::int64_t>(s.checks.motion_allowance_ms * 1e6);
  const std::int64_t window = ro.navigation.moved_window_ns;
  // The start of the drive under way at t, or -1.
  auto drive_began = [&](std::int64_t t) -> std::int64_t {
    for (auto [b, e] : platform->drives())
      if (b <= t && t < e) return b;
    return -1;
  };
  // Checked over time (every 10 ms of virtual time).
  int moved_flag_failures = 0, moving_grasp_failures = 0;
  host.every(10 * kMs, [&] {
    const std::int64_t t = host.now();
    if (nav >= 0 && host.up(nav) && host.runtime(nav) && started_at.count(nav) &&
        t - started_at[nav] > 200 * kMs) {
      const graph::Graph& g = *host.graph(nav);
      const NodeId robot = agm::node_id(g, agm::node::kRobot);
      const bool truth = platform->moved_between(t - window, t);
      const bool settled = truth == platform->moved_between(t - 40 * kMs - window, t - 40 * kMs);
      if (!robot.is_null() && settled && g.has_edge(robot, robot, agm::edge::kMoved) != truth &&
          moved_flag_failures++ < 3)
        fail("at " + fmt_s(t) + " movedInLastSeconds is " + (truth ? "absent" : "present") +
             " on navigation's replica, odometry says " + (truth ? "moved" : "still"));
    }
    if (grasping >= 0 && host.up(grasping) && host.graph(grasping)) {
      const graph::Graph& g = *host.graph(grasping);
      const NodeId robot = agm::node_id(g, agm::node::kRobot);
      const std::int64_t began = drive_began(t);
      if (!robot.is_null() && began >= 0 && t - began > allowance &&
          !g.edges_from(robot, agm::edge::kGrasping).empty() && moving_grasp_failures++ < 3)
        fail("at " + fmt_s(t) + " still grasping, the platform drives since " + fmt_s(began));
    }
  });

  // Run until the route is done and settled (or the limit).
  const auto limit = static_cast<std::int64_t>(s.limit_s * kSec);
  while (host.now() < limit) {
    host.run_until(host.now() + 100 * kMs);
    if (platform->started() && platform->finished(host.now()) &&
        host.now() > *platform->end_time() + 3 * kSec)
      break;
  }
  if (platform->finished(host.now()))
    r.finished_s = static_cast<double>(*platform->end_time()) / 1e9;
  else
    fail("the route did not end within " + std::to_string(s.limit_s) +
         " s (the platform waits for the grasp)");

  // Heal everything, bring every agent back, quiet the trackers, let the replicas settle.
  host.heal();
  host.set_loss(0);
  for (int i = 0; i < host.size(); ++i)
    if (!host.up(i)) host.restart(i);
  host.run_until(host.now() + 2 * kSec);

  {
    agm::LatencyProbe pooled;
    for (int i = 0; i < host.size(); ++i) {
      const agm::LatencyProbe* p = nullptr;
      if (auto* a = dynamic_cast<agm::Navigation*>(host.agent(i))) p = &a->probe();
      if (auto* a = dynamic_cast<agm::Rooms*>(host.agent(i))) p = &a->probe();
      if (auto* a = dynamic_cast<agm::Grasping*>(host.agent(i))) p = &a->probe();
      if (p) {
        json j;
        p->to_json(j);
        pooled.merge_json(j);
      }
      if (auto* h = dynamic_cast<agm::Humans*>(host.agent(i))) h->stop_tracking();
    }
    r.human_deliveries = pooled.count();
    r.human_latency_p99_ms = pooled.percentile_us(0.99) / 1e3;
  }
  host.run_until(host.now() + 5 * kSec);
  r.rejected = host.rejected();
  r.partitions = counts.partitions;
  r.kills = counts.kills;

  // Convergence: every replica holds the same state.
  r.converged = true;
  for (int i = 0; i < host.size(); ++i) {
    if (!host.graph(i)) {
      r.converged = false;
      continue;
    }
    if (host.graph(i)->digest() != host.graph(0)->digest()) r.converged = false;
  }
  if (!r.converged) fail("replicas differ after healing and 5 s of quiet");

  // The expected facts, on the first replica.
  const graph::Graph& g = *host.graph(0);
  const NodeId robot = agm::node_id(g, agm::node::kRobot), mug = agm::node_id(g, "mug");
  auto room = agm::room_of(g, robot);
  r.final_room = room ? g.name_of(*room) : "";
  if (r.final_room != "kitchen")
    fail("the robot ends in '" + r.final_room + "', not in the kitchen");
  if (!g.has_edge(robot, mug, agm::edge::kCarrying)) fail("the robot does not carry the mug");
  if (auto mr = agm::room_of(g, mug); !mr || g.name_of(*mr) != "kitchen")
    fail("the mug is in '" + (mr ? g.name_of(*mr) : std::string()) +
         "', not in the kitchen with the robot");
  if (g.has_edge(robot, robot, agm::edge::kMoved))
    fail("movedInLastSeconds still set on a parked robot");
  if (!g.edges_from(robot, agm::edge::kGrasping).empty())
    fail("a grasp still announced at the end");
  if (!g.has_edge(robot, mug, agm::edge::kReach) || g.has_edge(robot, mug, agm::edge::kNoReach))
    fail("the mug in the gripper is not (only) in reach");

  // changeRoom against the platform's crossings (sampled every ms of its true path).
  std::vector<std::pair<std::string, std::string>> expected;
  std::vector<std::int64_t> crossed_at;
  if (platform->started()) {
    std::string prev;
    const std::int64_t end = platform->end_time().value_or(host.now());
    for (std::int64_t t = platform->t0(); t <= end; t += kMs) {
      agm::Pose2 p = platform->pose(t);
      auto in = agm::room_at(g, p.x, p.y);
      std::string name = in ? g.name_of(*in) : prev;
      if (!prev.empty() && name != prev) {
        expected.emplace_back(prev, name);
        crossed_at.push_back(t);
      }
      prev = name;
    }
  }
  r.expected_room_changes = static_cast<int>(expected.size());
  r.room_changes = static_cast<int>(changes.size());
  const std::int64_t frame = static_cast<std::int64_t>(1e9 / ro.navigation.rate_hz);
  for (const agm::RoomChange& c : changes) {
    const agm::Pose2 truth = platform->pose(c.stamp_ns);
    auto to = g.find_node(c.to);
    auto limits = to ? agm::room_limits(g, *to)
                     : Result<agm::Polygon>(make_error(ErrorCode::kNotFound, c.to));
    if (!limits.ok() || !limits->contains(c.x, c.y))
      fail("changeRoom " + c.from + " -> " + c.to + " at " + fmt_s(c.committed_ns) +
           " on a pose outside " + c.to);
    if (std::hypot(truth.x - c.x, truth.y - c.y) > 0.01)
      fail("changeRoom " + c.from + " -> " + c.to + " on a pose the platform never had");
    if (s.checks.exact_crossings) {
      const agm::Pose2 before = platform->pose(c.stamp_ns - 2 * frame);
      auto was = agm::room_at(g, before.x, before.y);
      if (!was || g.name_of(*was) != c.from)
        fail("changeRoom " + c.from + " -> " + c.to +
             " late: two frames before its pose the robot was already out of " + c.from);
      if (static_cast<double>(c.committed_ns - c.stamp_ns) > s.checks.crossing_lag_ms * 1e6)
        fail("changeRoom " + c.from + " -> " + c.to + " committed " +
             std::to_string((c.committed_ns - c.stamp_ns) / kMs) + " ms after its pose");
    }
  }
  if (s.checks.exact_crossings) {
    std::vector<std::pair<std::string, std::string>> got;
    for (const auto& c : changes) got.emplace_back(c.from, c.to);
    if (got != expected)
      fail("changeRoom issued " + std::to_string(got.size()) + " times, the platform crossed " +
           std::to_string(expected.size()) + " room limits (or in another order)");
  } else if (changes.size() < expected.size()) {
    fail("fewer changeRoom (" + std::to_string(changes.size()) + ") than crossings (" +
         std::to_string(expected.size()) + ")");
  }

  // reach / noReach and the grasp.
  std::map<std::string, std::int64_t> run_started;
  for (const agm::GraspEvent& e : grasp_events) {
    switch (e.kind) {
      case agm::GraspEvent::Kind::kReach: {
        ++r.reach_changes;
        const double truth = gripper_mug_distance(platform->pose(e.stamp_ns));
        if (e.distance >= ro.grasping.reach_on_m || truth >= ro.grasping.reach_on_m + 0.01)
          fail("reach set at " + fmt_s(e.t_ns) + " with FCL distance " +
               std::to_string(e.distance) + " m (true " + std::to_string(truth) +
               " m), threshold " + std::to_string(ro.grasping.reach_on_m) + " m");
        break;
      }
      case agm::GraspEvent::Kind::kNoReach:
        ++r.reach_changes;
        fail("noReach set again at " + fmt_s(e.t_ns) + " (distance " + std::to_string(e.distance) +
             " m): reach flickered");
        break;
      case agm::GraspEvent::Kind::kStarted:
        run_started[e.object] = e.t_ns;
        break;
      case agm::GraspEvent::Kind::kPaused:
        ++r.pauses;
        break;
      case agm::GraspEvent::Kind::kGrasped: {
        ++r.grasps;
        r.grasped_s = static_cast<double>(e.t_ns) / 1e9;
        const std::int64_t began = run_started.count(e.object) ? run_started[e.object] : e.t_ns;
        for (auto [b, en] : platform->drives())
          if (en > began && b < e.t_ns - allowance)
            fail("grasped at " + fmt_s(e.t_ns) + " though the platform drove from " + fmt_s(b) +
                 " to " + fmt_s(en) + " during the grasp (from " + fmt_s(began) + ")");
        break;
      }
    }
  }
  if (r.reach_changes == 0) fail("reach never set");
  if (r.grasps == 0) fail("the mug was never grasped");
  if (s.checks.exact_crossings && r.grasps != 1)
    fail("grasped " + std::to_string(r.grasps) + " times");
  if (s.checks.expect_pause && r.pauses == 0) fail("the nudge mid-grasp did not pause the grasp");
  if (s.humans && r.human_deliveries == 0) fail("no human joint pose reached the other agents");
  r.passed = r.failures.empty();
  return r;
}

}  // namespace quiver::agents::inline apps::agm
