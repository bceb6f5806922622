// The team scenario registered with the simulator (team_scenario.h): roles per robot, the devices
// the robots share (their platforms, the hands' custody of the mugs), when a run is done, how it
// settles, its checks and figures, and its random fault schedules.
#include <algorithm>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>

#include "quiver/agents/apps/agm/agm_roles.h"
#include "quiver/agents/apps/agm/sim/team_scenario.h"
#include "quiver/agents/apps/agm/team_world.h"
#include "quiver/base/rng.h"
#include "quiver/sim/fault_generator.h"
#include "quiver/sim/scenario.h"
#include "quiver/sim/scenario_run.h"

namespace quiver::agents::inline apps::agm {
// Named, not anonymous: the unity build puts this file beside agm_app.cc.
namespace team_sim {

using graph::NodeId;
using nlohmann::json;
constexpr std::int64_t kMilli = 1'000'000;
constexpr std::int64_t kSecond = 1'000'000'000;
// What a robot's agents are, in order after its gateway; robot A's fifth tracks the people.
const char* const kWorkers[] = {"navigation", "rooms", "grasping", "planner"};
constexpr int kMaxIdle = 24;
const char* const kMugs[] = {"mug", "mug2"};

class Idle final : public Agent {
 public:
  using Agent::Agent;
  void setup(AgentContext&) override {}
};

struct TeamSettings {
  int robots = 2, agents_per_robot = 6;
  double humans_hz = 30, team_loss = 0;
  bool guards = true;
};

TeamSettings team_settings(const json& j) {
  TeamSettings s;
  s.robots = j.value("robots", s.robots);
  s.agents_per_robot = j.value("agents_per_robot", s.agents_per_robot);
  s.humans_hz = j.value("humans_hz", s.humans_hz);
  s.team_loss = j.value("team_loss", s.team_loss);
  s.guards = j.value("guards", s.guards);
  return s;
}

std::vector<std::string> names_of(const TeamSettings& s) {
  std::vector<std::string> out;
  for (const TeamRobot& r : team_robots(s.robots)) {
    for (const char* w : kWorkers) out.push_back(r.tag + "-" + w);
    out.push_back(r.tag + (r.tag == "A" ? "-humans" : "-idle1"));
    for (int k = 6, idle = r.tag == "A" ? 1 : 2; k < s.agents_per_robot; ++k, ++idle)
      out.push_back(r.tag + "-idle" + std::to_string(idle));
  }
  return out;
}

// What the robots share over one run and what the checks gather.
struct TeamRun {
  TeamSettings settings;
  std::vector<TeamRobot> team;
  std::vector<std::shared_ptr<Platform>> platforms;  // outlive their navigation agents
  std::shared_ptr<SharedCustody> custody = std::make_shared<SharedCustody>();
  struct Grasp {
    int robot;
    GraspEvent e;
  };
  std::vector<Grasp> grasps;
  std::vector<std::string> over_time;  // what failed while it ran (first few)
  std::int64_t achieved_at = -1;
  // Convergence after each heal of the team network: the ms until every replica held what any
  // replica held at the heal.
  std::vector<double> heal_converge_ms;
  // Robot -> how many times a replica of it held a newer pose of a tracked joint (sampled).
  std::map<std::string, std::uint64_t> joints_seen;
  std::map<std::string, std::int64_t> last_joint_stamp;
  bool converged = false;

  void fail(std::string what) {
    if (over_time.size() < 10) over_time.push_back(std::move(what));
  }
};

TeamRun& team_run(sim::ScenarioRun& run) { return *run.state_as<std::shared_ptr<TeamRun>>(); }

int robot_index(const std::string& role) { return role.empty() ? -1 : role[0] - 'A'; }

// Every replica up (each agent's, and both sides of each gateway), with its replicator.
struct Up {
  graph::Graph* graph;
  agents::Replicator* replicator;
};
std::vector<Up> replicas(sim::AgentHost& host) {
  std::vector<Up> out;
  for (int i = 0; i < host.size(); ++i)
    if (host.up(i) && host.graph(i)) out.push_back({host.graph(i), host.replicator(i)});
  for (int r = 0; r < host.robots(); ++r)
    for (int side = 0; side < 2; ++side)
      if (graph::Graph* g = host.gateway_graph(r, side)) out.push_back({g, host.gateway_replicator(r, side)});
  return out;
}

std::string plan_status(const graph::Graph& g, const TeamRobot& r) {
  const NodeId plan = node_id(g, r.names.plan);
  const graph::Value* v = plan.is_null() ? nullptr : g.attr(plan, "status");
  const auto* s = v ? v->get_if<std::string>() : nullptr;
  return s ? *s : std::string();
}

// Whether every robot's own planner says its plan is achieved, on its own replica.
bool all_achieved(sim::ScenarioRun& run) {
  TeamRun& st = team_run(run);
  sim::AgentHost& host = run.host();
  for (const TeamRobot& r : st.team) {
    const int i = host.index(r.tag + "-planner");
    if (i < 0 || !host.up(i) || !host.graph(i) || plan_status(*host.graph(i), r) != "achieved") return false;
  }
  return true;
}

// No mug carried by two robots, on any replica.
void sample_carriers(sim::ScenarioRun& run) {
  TeamRun& st = team_run(run);
  for (const Up& u : replicas(run.host()))
    for (const char* mug : kMugs) {
      const graph::Graph& g = *u.graph;
      const NodeId m = node_id(g, mug);
      if (m.is_null()) continue;
      const auto carriers = g.edges_to(m, edge::kCarrying);
      if (carriers.size() > 1)
        st.fail("t=" + std::to_string(run.host().now() / kMilli) + " ms: " + mug + " carried by " +
                g.name_of(carriers[0].from) + " and " + g.name_of(carriers[1].from) + " on the replica of " +
                g.replica().to_string());
    }
}

// Whether the people's joints, tracked on robot A, reach the other robots: a replica of each
// (its first agent up) holds ever newer poses of one joint.
void sample_joints(sim::ScenarioRun& run) {
  TeamRun& st = team_run(run);
  sim::AgentHost& host = run.host();
  for (const TeamRobot& r : st.team) {
    if (r.tag == "A") continue;
    for (int i = 0; i < host.size(); ++i) {
      if (host.robot_of(i) != host.robot_index(r.tag) || !host.up(i) || !host.graph(i)) continue;
      const graph::Graph& g = *host.graph(i);
      const NodeId head = node_id(g, "person0_head");
      const auto rt = head.is_null() ? std::nullopt : g.rt_edge(head);
      if (rt && rt->stamp > st.last_joint_stamp[r.tag]) {
        st.last_joint_stamp[r.tag] = rt->stamp;
        ++st.joints_seen[r.tag];
      }
      break;
    }
  }
}

// After a heal: how long until every replica holds what any replica held at the heal (not
// counted when the next fault comes first, at `until`).
void watch_heal(sim::ScenarioRun& run, std::int64_t until) {
  auto target = std::make_shared<crdt::CausalContext>();
  for (const Up& u : replicas(run.host())) target->join(u.replicator->applied());
  const std::int64_t t0 = run.host().now();
  auto poll = std::make_shared<std::function<void()>>();
  *poll = [&run, target, t0, until, poll] {
    bool all = true;
    for (const Up& u : replicas(run.host())) all = all && u.replicator->applied().includes(*target);
    if (all) {
      team_run(run).heal_converge_ms.push_back(static_cast<double>(run.host().now() - t0) / 1e6);
      return;
    }
    if (run.host().now() < until) run.host().at(run.host().now() + kMilli, *poll);
  };
  run.host().at(t0, *poll);
}

Status start(sim::ScenarioRun& run) {
  auto st = std::make_shared<TeamRun>();
  st->settings = team_settings(run.scenario().settings);
  st->team = team_robots(st->settings.robots);
  for (const TeamRobot& r : st->team) st->platforms.push_back(std::make_shared<Platform>(std::vector<Leg>{}, r.start));
  run.state() = st;
  sim::AgentHost& host = run.host();
  host.set_team_loss(st->settings.team_loss);
  host.every(10 * kMilli, [&run] { sample_carriers(run); });
  host.every(100 * kMilli, [&run] { sample_joints(run); });
  const auto& faults = run.scenario().faults;
  for (const sim::FaultEvent& f : faults) {
    if (f.kind != sim::FaultEvent::Kind::kHeal) continue;
    const auto at = static_cast<std::int64_t>(f.at_s * 1e9);
    std::int64_t until = at + 30 * kSecond;
    for (const sim::FaultEvent& g : faults)
      if (g.at_s > f.at_s && g.kind != sim::FaultEvent::Kind::kLoss) until = std::min(until, static_cast<std::int64_t>(g.at_s * 1e9));
    host.at(at + 1, [&run, until] { watch_heal(run, until); });
  }
  return {};
}

// Done once every robot's plan is achieved and every platform stood idle for 2 s.
bool done(sim::ScenarioRun& run) {
  TeamRun& st = team_run(run);
  const std::int64_t now = run.host().now();
  bool idle = true;
  for (const auto& p : st.platforms) idle = idle && p->finished(now) && now > p->end_time().value_or(0) + 2 * kSecond;
  if (!all_achieved(run) || !idle) {
    st.achieved_at = -1;
    return false;
  }
  if (st.achieved_at < 0) st.achieved_at = now;
  return now > st.achieved_at + 2 * kSecond;
}

void settle_team(sim::ScenarioRun& run) {
  TeamRun& st = team_run(run);
  sim::AgentHost& host = run.host();
  host.heal();
  host.set_loss(0);
  for (const TeamRobot& r : st.team) (void)host.restart(r.tag);  // whatever of it is down
  host.run_until(host.now() + 2 * kSecond);
  for (int i = 0; i < host.size(); ++i) {
    const std::string& name = host.name(i);
    if (auto* h = dynamic_cast<Humans*>(host.agent(i))) h->stop_tracking();
  }
  host.run_until(host.now() + 5 * kSecond);
  const std::vector<Up> all = replicas(host);
  const std::size_t expected = static_cast<std::size_t>(host.size() + 2 * host.robots());
  st.converged = all.size() == expected;
  for (const Up& u : all) st.converged = st.converged && u.graph->digest() == all.front().graph->digest();
}

const graph::Graph* final_replica(sim::ScenarioRun& run) {
  sim::AgentHost& host = run.host();
  return host.size() > 0 && host.up(0) ? host.graph(0) : nullptr;
}

void check_end(sim::ScenarioRun& run, std::vector<std::string>& f) {
  TeamRun& st = team_run(run);
  for (const std::string& s : st.over_time) f.push_back(s);
  if (!st.converged) f.push_back("the replicas did not converge (agents and both sides of every gateway)");
  const graph::Graph* g = final_replica(run);
  if (!g) {
    f.push_back("no final replica");
    return;
  }
  const NodeId kitchen = node_id(*g, "kitchen");
  for (const char* mug : kMugs) {
    const NodeId m = node_id(*g, mug);
    if (m.is_null()) {
      f.push_back(std::string(mug) + " is gone");
      continue;
    }
    const auto room = room_of(*g, m);
    if (!room || *room != kitchen)
      f.push_back(std::string(mug) + " ends in " + (room ? g->name_of(*room) : std::string("no room")) + ", not the kitchen");
    if (!g->edges_from(m, edge::kOn).empty()) f.push_back(std::string(mug) + " is still on the table");
    if (!g->edges_to(m, edge::kCarrying).empty()) f.push_back(std::string(mug) + " is still carried");
    if (const std::string h = st.custody->holder(mug); !h.empty()) f.push_back(std::string(mug) + " is still in " + h + "'s hand");
  }
  for (const TeamRobot& r : st.team)
    if (const std::string s = plan_status(*g, r); s != "achieved")
      f.push_back("robot " + r.tag + "'s plan is '" + s + "', not achieved");
  // No grasp started while its robot moved; none completed unless it stood still through it.
  const std::int64_t allowance = 500 * kMilli;
  for (const TeamRun::Grasp& gr : st.grasps) {
    const Platform& p = *st.platforms[static_cast<std::size_t>(gr.robot)];
    const std::string who = "robot " + st.team[static_cast<std::size_t>(gr.robot)].tag;
    if (gr.e.kind == GraspEvent::Kind::kStarted && p.moving(gr.e.t_ns))
      f.push_back(who + " started grasping " + gr.e.object + " at " + std::to_string(gr.e.t_ns / kMilli) + " ms while it moved");
    if (gr.e.kind == GraspEvent::Kind::kGrasped &&
        p.moved_between(gr.e.t_ns - 1'500 * kMilli + allowance, gr.e.t_ns))
      f.push_back(who + " grasped " + gr.e.object + " at " + std::to_string(gr.e.t_ns / kMilli) + " ms though it moved during the grasp");
  }
  for (const TeamRobot& r : st.team)
    if (r.tag != "A" && st.joints_seen[r.tag] == 0) f.push_back("the joints tracked on robot A never reached robot " + r.tag);
}

void report(sim::ScenarioRun& run, json& m) {
  TeamRun& st = team_run(run);
  sim::AgentHost& host = run.host();
  m["robots"] = st.settings.robots;
  m["agents_per_robot"] = st.settings.agents_per_robot;
  m["converged"] = st.converged;
  json fetched = json::object(), per_robot = json::object();
  int grasps = 0, misses = 0, pauses = 0;
  for (const TeamRun::Grasp& gr : st.grasps) {
    const std::string& tag = st.team[static_cast<std::size_t>(gr.robot)].tag;
    if (gr.e.kind == GraspEvent::Kind::kGrasped) {
      ++grasps;
      fetched[gr.e.object] = tag;
      per_robot[tag] = per_robot.value(tag, 0) + 1;
    }
    if (gr.e.kind == GraspEvent::Kind::kMissed) ++misses;
    if (gr.e.kind == GraspEvent::Kind::kPaused) ++pauses;
  }
  m["fetched_by"] = fetched;
  m["grasps"] = grasps;
  m["grasps_by_robot"] = per_robot;
  m["misses"] = misses;
  m["pauses"] = pauses;
  std::int64_t replans = 0;
  if (const graph::Graph* g = final_replica(run))
    for (const TeamRobot& r : st.team) {
      const NodeId plan = node_id(*g, r.names.plan);
      const graph::Value* v = plan.is_null() ? nullptr : g->attr(plan, "replans");
      if (v && v->get_if<std::int64_t>()) replans += *v->get_if<std::int64_t>();
    }
  m["replans"] = replans;
  m["team_bytes"] = host.team_bytes();
  m["bytes"] = host.network().stats().bytes;
  m["heal_converge_ms"] = st.heal_converge_ms;
  m["joints_seen"] = st.joints_seen;
  double done_s = 0;
  for (const auto& p : st.platforms) done_s = std::max(done_s, static_cast<double>(p->end_time().value_or(0)) / 1e9);
  m["finished_s"] = done_s;
}

std::unique_ptr<Agent> make_agent(sim::ScenarioRun& run, const std::string& role) {
  TeamRun& st = team_run(run);
  const int r = robot_index(role);
  if (r < 0 || r >= static_cast<int>(st.team.size())) return nullptr;
  const std::string kind = role.substr(2);
  if (kind.rfind("idle", 0) == 0) return std::make_unique<Idle>(role);
  AgmRoleOptions o;
  o.name = role;
  o.team = st.team[static_cast<std::size_t>(r)];
  o.team_size = st.settings.robots;
  o.platform = st.platforms[static_cast<std::size_t>(r)];
  o.navigation.quiet_when_done = true;
  if (st.settings.guards) o.grasping.custody = st.custody;
  o.grasping.on_event = [s = &st, r, &run](const GraspEvent& e) {
    s->grasps.push_back({r, e});
    run.note("robot " + s->team[static_cast<std::size_t>(r)].tag + ": " + e.name() + " " + e.object +
             (e.kind == GraspEvent::Kind::kReach || e.kind == GraspEvent::Kind::kNoReach
                  ? " (distance " + std::to_string(e.distance) + " m)"
                  : std::string()));
  };
  o.humans.rate_hz = st.settings.humans_hz;
  auto a = make_role(kind == "planner" ? std::string(kPlannerRole) : kind, o);
  if (a.ok() && !st.settings.guards)
    if (auto* g = dynamic_cast<Grasping*>(a->get())) g->drop_object_locks();
  return a.ok() ? std::move(*a) : nullptr;
}

sim::ScenarioApp make_app() {
  sim::ScenarioApp app("agm-team");
  app.default_agents([](const json& settings) { return names_of(team_settings(settings)); });
  app.default_world([](const json& settings) {
    auto w = team_world_json(team_settings(settings).robots);
    return w.ok() ? *w : std::string();
  });
  app.team([](const json& settings) {
    sim::AgentHostOptions::Team t;
    for (const TeamRobot& r : team_robots(team_settings(settings).robots)) t.robots.push_back(r.tag);
    t.links.delay_min_ns = 2 * kMilli;  // a wireless link between robots
    t.links.delay_max_ns = 10 * kMilli;
    return t;
  });
  for (const TeamRobot& r : team_robots(kMaxTeamRobots)) {
    std::vector<std::string> kinds(std::begin(kWorkers), std::end(kWorkers));
    kinds.push_back("humans");
    for (int k = 1; k <= kMaxIdle; ++k) kinds.push_back("idle" + std::to_string(k));
    for (const std::string& kind : kinds)
      app.role(r.tag + "-" + kind, [role = r.tag + "-" + kind](sim::ScenarioRun& run) { return make_agent(run, role); });
  }
  app.settings([](const json& keys, const std::string& source) -> Status {
    for (auto it = keys.begin(); it != keys.end(); ++it)
      if (it.key() != "robots" && it.key() != "agents_per_robot" && it.key() != "humans_hz" && it.key() != "team_loss" &&
          it.key() != "guards")
        return Error{ErrorCode::kInvalidArgument, source + ": unknown key '" + it.key() + "'"};
    const TeamSettings s = team_settings(keys);
    if (s.robots < 2 || s.robots > kMaxTeamRobots)
      return Error{ErrorCode::kInvalidArgument, source + ": /robots must be 2 to " + std::to_string(kMaxTeamRobots)};
    if (s.agents_per_robot < 6 || s.agents_per_robot > 5 + kMaxIdle)
      return Error{ErrorCode::kInvalidArgument, source + ": /agents_per_robot must be 6 to " + std::to_string(5 + kMaxIdle)};
    return {};
  });
  app.stores(true);  // --durability always: a crashed robot comes back with what it knew
  app.on_start(start);
  app.done_when(done);
  app.settle(settle_team);
  app.report(report);
  app.check("team", sim::switch_check(check_end));
  return app;
}

}  // namespace team_sim

const sim::ScenarioApp& team_app() {
  static const sim::ScenarioApp app = team_sim::make_app();
  return app;
}

std::vector<std::string> TeamScenario::agent_names() const {
  team_sim::TeamSettings s;
  s.robots = robots;
  s.agents_per_robot = agents_per_robot;
  return team_sim::names_of(s);
}

TeamScenario TeamScenario::random_faults(std::uint64_t seed, int robots, int agents_per_robot) {
  Rng rng(seed ^ 0x7ea3c0ffee5ULL);
  TeamScenario s;
  s.name = "agm-team-faults";
  s.robots = robots;
  s.agents_per_robot = agents_per_robot;
  sim::FaultMix mix;
  for (const TeamRobot& r : team_robots(robots)) {
    mix.agents.push_back(r.tag);
    mix.killable.push_back(r.tag);
    mix.killable.push_back(r.tag + "-gateway");
  }
  mix.min_partitions = 1;
  mix.max_partitions = 2;
  mix.fill_groups = true;
  mix.partitions_in_turn = true;
  mix.partition_at = {3, 30};
  mix.heal_after = {2, 10};
  mix.max_kills = 2;
  mix.kill_at = {2, 30};
  mix.restart_after = {0.5, 3};
  mix.loss_at = {0, 20};
  s.faults = sim::random_faults(rng, mix);
  return s;
}

TeamResult run_team_scenario(const TeamScenario& s, std::uint64_t seed,
                             std::function<void(std::int64_t, const std::string&)> log) {
  sim::Scenario g;
  g.name = s.name;
  g.app = "agm-team";
  g.faults = s.faults;
  g.settings = {{"robots", s.robots}, {"agents_per_robot", s.agents_per_robot}, {"humans_hz", s.humans_hz},
                {"team_loss", s.team_loss}, {"guards", s.guards}};
  g.checks = {{"team", true}};
  g.limit_s = s.limit_s;
  for (const std::string& n : s.agent_names()) g.agents.push_back({n, n});
  return sim::run_scenario(g, team_app(), seed, std::move(log));
}

}  // namespace quiver::agents::inline apps::agm
