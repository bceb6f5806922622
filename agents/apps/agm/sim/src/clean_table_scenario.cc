// The clean-the-table mission in the simulator: the AGM agents and the planner agent (no
// executive: the plan lives in the graph), with a fault schedule, and the checks of
// agm_scenario.h (AgmScenario::mission).
#include <algorithm>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "quiver/agents/apps/agm/clean_table.h"
#include "quiver/agents/apps/agm/agm_roles.h"
#include "quiver/agents/apps/agm/agm_schema.h"
#include "quiver/agents/apps/planning/planner_agent.h"
#include "quiver/sim/agent_host.h"
#include "quiver/sim/fault_model.h"
#include "quiver/agents/apps/agm/sim/agm_scenario.h"
#include "quiver/sim/simulator.h"

namespace quiver::agents::inline apps::agm {

using namespace quiver::sim;  // the simulator this scenario runs on

using graph::NodeId;

namespace {

constexpr std::int64_t kMs = 1'000'000;
constexpr std::int64_t kSec = 1'000'000'000;

std::string fmt_s(std::int64_t t) {
  std::ostringstream o;
  o.precision(3);
  o << std::fixed << static_cast<double>(t) / 1e9 << " s";
  return o.str();
}

std::string string_attr(const graph::Graph& g, NodeId n, const char* name) {
  const graph::Value* v = n.is_null() ? nullptr : g.attr(n, name);
  const auto* s = v ? v->get_if<std::string>() : nullptr;
  return s ? *s : std::string();
}

std::int64_t int_attr(const graph::Graph& g, NodeId n, const char* name) {
  const graph::Value* v = n.is_null() ? nullptr : g.attr(n, name);
  const auto* i = v ? v->get_if<std::int64_t>() : nullptr;
  return i ? *i : 0;
}

// Someone in the house: at `at_ns` it puts the mug back on the table (if the robot does not carry
// it), under its own grammar. The clean-the-table plan no longer reaches the mission from there.
constexpr const char* kPersonGrammar = R"(grammar person
types {
  room
  table
  object
  mug : object
}
allow attributes
allow rt-poses
allow rt-moves
rule putBack : active {
  { o:object t:table a:room b:room  o->a(in)  t->b(in)  !o->t(on) }
  =>
  { o:object t:table a:room b:room  o->b(in)  t->b(in)  o->t(on) }
}
)";

class PutBack final : public agents::Agent {
 public:
  explicit PutBack(std::int64_t at_ns) : Agent("person"), at_ns_(at_ns) {
    set_grammar_text(kPersonGrammar, "person.aggl");
  }
  void setup(agents::AgentContext& ctx) override {
    ctx.every(100 * kMs, [this, &ctx] {
      if (done_ || ctx.now() < at_ns_) return;
      graph::Graph& g = ctx.graph();
      const NodeId mug = agm::node_id(g, "mug"), table = agm::node_id(g, "table"),
                   robot = agm::node_id(g, agm::node::kRobot),
                   world = agm::node_id(g, agm::node::kWorld);
      if (mug.is_null() || table.is_null() || world.is_null() ||
          g.has_edge(mug, table, agm::edge::kOn) || g.has_edge(robot, mug, agm::edge::kCarrying) ||
          g.has_edge(robot, mug, agm::edge::kGrasping))
        return;
      auto from = agm::room_of(g, mug), to = agm::room_of(g, table);
      if (!from || !to || *from == *to) return;
      graph::Transaction tx = g.begin();
      graph::Pose X_WM;
      X_WM.translation = {8.70, 2.0, 0.81};
      Status st = tx.delete_edge(mug, *from, graph::Symbol(agm::edge::kIn));
      if (st.ok()) st = tx.insert_edge(mug, *to, graph::Symbol(agm::edge::kIn));
      if (st.ok()) st = tx.insert_edge(mug, table, graph::Symbol(agm::edge::kOn));
      if (st.ok()) st = tx.set_rt(world, mug, X_WM, ctx.now());
      if (st.ok()) {
        if (auto c = tx.commit(); !c.ok()) st = c.error();
      }
      if (!st.ok()) {
        ctx.log("putBack refused: " + st.error().to_string());
        return;
      }
      done_ = true;
      ctx.log("a person put the mug back on the table");
    });
  }

 private:
  std::int64_t at_ns_;
  bool done_ = false;
};

}  // namespace

AgmResult run_agm_clean_table(const AgmScenario& s, std::uint64_t seed,
                              std::function<void(std::int64_t, const std::string&)> log) {
  AgmResult r;
  r.name = s.name;
  r.seed = seed;
  auto fail = [&](const std::string& f) {
    if (r.failures.size() < 20) r.failures.push_back(f);
  };
  const bool faults = !s.faults.empty();

  // The platform outlives the navigation agent's incarnations; it has no fixed route.
  auto platform = std::make_shared<agm::Platform>(std::vector<agm::Leg>{}, agm::default_start());
  std::vector<agm::RoomChange> changes;
  std::vector<agm::GraspEvent> grasp_events;
  agm::AgmRoleOptions ro;
  ro.platform = platform;
  ro.clean_table = true;
  ro.navigation.quiet_when_done = true;
  ro.rooms.on_change = [&](const agm::RoomChange& c) { changes.push_back(c); };
  ro.grasping.on_event = [&](const agm::GraspEvent& e) { grasp_events.push_back(e); };
  ro.humans.rate_hz = s.humans_hz;
  ro.grasping.reach_off_m = s.reach_off_m;
  ro.measure_humans = s.humans;

  std::vector<std::string> roles = agm::role_names();
  roles.push_back(agm::kPlannerRole);
  std::vector<SimAgentSpec> specs;
  for (const std::string& role : roles) {
    if (role == "humans" && !s.humans) continue;
    specs.push_back({role, [&ro, role]() -> std::unique_ptr<agents::Agent> {
                       auto a = agm::make_role(role, ro);
                       return a.ok() ? std::move(*a) : nullptr;
                     }});
  }
  if (s.put_back_s > 0) {
    const auto at = static_cast<std::int64_t>(s.put_back_s * 1e9);
    specs.push_back({"person", [at]() -> std::unique_ptr<agents::Agent> {
                       return std::make_unique<PutBack>(at);
                     }});
  }
  AgentHostOptions ho;
  ho.seed = seed;
  ho.replicator = SimConfig::default_replicator();
  ho.locks.lease_ns = kSec;
  ho.world_json = std::string(agm::embedded_file("clean-table.json"));
  ho.log = log;
  AgentHost host(std::move(specs), ho);
  if (Status st = host.start(); !st.ok()) {
    fail(st.error().to_string());
    return r;
  }
  sim::FaultCounts counts;
  schedule_faults(host, s.faults, log, counts);

  const int planner = host.index(agm::kPlannerRole), grasping = host.index("grasping");
  const std::int64_t allowance = static_cast<std::int64_t>(s.checks.motion_allowance_ms * 1e6);
  auto drive_began = [&](std::int64_t t) -> std::int64_t {
    for (auto [b, e] : platform->drives())
      if (b <= t && t < e) return b;
    return -1;
  };
  // Over time (every 10 ms): the plans the planner wrote (by version, from its replica), and
  // never a grasp running while the platform drives.
  std::map<std::int64_t, std::string> plans;
  int moving_grasp_failures = 0;
  host.every(10 * kMs, [&] {
    const std::int64_t t = host.now();
    if (planner >= 0 && host.up(planner) && host.graph(planner)) {
      const graph::Graph& g = *host.graph(planner);
      const NodeId plan = agm::node_id(g, "plan");
      const std::int64_t v = int_attr(g, plan, "version");
      const std::string steps = string_attr(g, plan, "steps");
      if (v > 0 && !steps.empty() && !plans.count(v)) {
        plans[v] = steps;
        if (log) log(t, "plan " + std::to_string(v) + ":\n" + steps);
      }
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

  // Run until the plan is achieved on the planner's replica and the platform is idle.
  const auto limit = static_cast<std::int64_t>(s.limit_s * kSec);
  std::int64_t achieved_at = -1;
  while (host.now() < limit) {
    host.run_until(host.now() + 100 * kMs);
    const graph::Graph* g = planner >= 0 && host.up(planner) ? host.graph(planner) : nullptr;
    const bool achieved = g && string_attr(*g, agm::node_id(*g, "plan"), "status") == "achieved";
    if (achieved && achieved_at < 0) achieved_at = host.now();
    if (!achieved) achieved_at = -1;
    if (achieved_at >= 0 && platform->finished(host.now()) && host.now() > achieved_at + 2 * kSec)
      break;
  }
  if (achieved_at < 0) fail("the plan was not achieved within " + std::to_string(s.limit_s) + " s");
  r.finished_s = static_cast<double>(platform->end_time().value_or(0)) / 1e9;

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
        nlohmann::json j;
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

  r.converged = true;
  for (int i = 0; i < host.size(); ++i)
    if (!host.graph(i) || host.graph(i)->digest() != host.graph(0)->digest()) r.converged = false;
  if (!r.converged) fail("replicas differ after healing and 5 s of quiet");

  // The mission on the final replica, and the plan node.
  const graph::Graph& g = *host.graph(0);
  agm::CleanTableReport rep = agm::check_clean_table(g);
  r.mission_holds = rep.mission_holds;
  r.plan_status = rep.plan_status;
  r.plan_version = rep.version;
  r.replans = rep.replans;
  if (!rep.mission_holds) {
    std::string why;
    for (const auto& m : rep.missing) why += (why.empty() ? "" : "; ") + m;
    fail("the mission does not hold on the final replica: " + why);
  }
  if (rep.plan_status != "achieved") fail("the plan node says '" + rep.plan_status + "'");
  // The first plan, as the planner agent wrote it, through the grammar guard from the world.
  if (plans.empty()) {
    fail("no plan was seen in the planner's replica");
  } else {
    const std::string& first = plans.begin()->second;
    r.plan_steps = static_cast<int>(std::count(first.begin(), first.end(), '\n'));
    Status v = agm::verify_clean_table_plan(first);
    r.plan_verified = v.ok() ? "ok" : v.error().to_string();
    if (!v.ok())
      fail("the first plan does not replay through the grammar guard: " + r.plan_verified);
    if (plans.begin()->first != 1)
      fail("the first plan seen is version " + std::to_string(plans.begin()->first));
  }
  const bool deviates = s.put_back_s > 0;
  if (deviates && rep.replans < 1)
    fail("the mug was put back on the table, yet the planner never replanned");
  if (!faults && !deviates && rep.replans != 0)
    fail("the planner replanned " + std::to_string(rep.replans) + " times without faults");
  const NodeId robot = agm::node_id(g, agm::node::kRobot);
  auto room = agm::room_of(g, robot);
  r.final_room = room ? g.name_of(*room) : "";
  if (g.has_edge(robot, robot, agm::edge::kMoved))
    fail("movedInLastSeconds still set on a parked robot");
  if (!g.edges_from(robot, agm::edge::kGrasping).empty())
    fail("a grasp still announced at the end");

  // Crossings of room limits against changeRoom.
  std::vector<std::pair<std::string, std::string>> expected;
  {
    std::string prev;
    const std::int64_t end = platform->end_time().value_or(host.now());
    for (std::int64_t t = platform->t0(); t <= end; t += kMs) {
      agm::Pose2 p = platform->pose(t);
      auto in = agm::room_at(g, p.x, p.y);
      std::string name = in ? g.name_of(*in) : prev;
      if (!prev.empty() && name != prev) expected.emplace_back(prev, name);
      prev = name;
    }
  }
  r.expected_room_changes = static_cast<int>(expected.size());
  r.room_changes = static_cast<int>(changes.size());
  if (!faults) {
    std::vector<std::pair<std::string, std::string>> got;
    for (const auto& c : changes) got.emplace_back(c.from, c.to);
    if (got != expected)
      fail("changeRoom issued " + std::to_string(got.size()) + " times, the platform crossed " +
           std::to_string(expected.size()) + " room limits (or in another order)");
  } else if (changes.size() < expected.size()) {
    fail("fewer changeRoom (" + std::to_string(changes.size()) + ") than crossings (" +
         std::to_string(expected.size()) + ")");
  }

  // Grasps and releases: each while the platform stood still.
  std::map<std::string, std::int64_t> run_started;
  std::map<std::string, int> grasped, released;
  for (const agm::GraspEvent& e : grasp_events) {
    switch (e.kind) {
      case agm::GraspEvent::Kind::kReach:
        ++r.reach_changes;
        if (e.distance >= ro.grasping.reach_on_m)
          fail("reach of " + e.object + " set at FCL distance " + std::to_string(e.distance));
        break;
      case agm::GraspEvent::Kind::kNoReach:
        ++r.reach_changes;
        break;
      case agm::GraspEvent::Kind::kStarted:
        run_started[e.object] = e.t_ns;
        break;
      case agm::GraspEvent::Kind::kPaused:
        ++r.pauses;
        break;
      case agm::GraspEvent::Kind::kGrasped: {
        ++r.grasps;
        ++grasped[e.object];
        r.grasped_s = static_cast<double>(e.t_ns) / 1e9;
        const std::int64_t began = run_started.count(e.object) ? run_started[e.object] : e.t_ns;
        for (auto [b, en] : platform->drives())
          if (en > began && b < e.t_ns - allowance)
            fail("grasped " + e.object + " at " + fmt_s(e.t_ns) +
                 " though the platform drove from " + fmt_s(b) + " to " + fmt_s(en));
        break;
      }
      case agm::GraspEvent::Kind::kReleased:
        ++r.releases;
        ++released[e.object];
        if (platform->moved_between(e.t_ns - ro.navigation.moved_window_ns + allowance, e.t_ns))
          fail("released " + e.object + " at " + fmt_s(e.t_ns) + " while the platform moved");
        break;
    }
  }
  for (const char* mug : {"mug", "mug2"}) {
    if (grasped[mug] == 0) fail(std::string(mug) + " was never grasped");
    if (released[mug] == 0) fail(std::string(mug) + " was never released");
    if (!faults && !deviates && (grasped[mug] != 1 || released[mug] != 1))
      fail(std::string(mug) + " grasped " + std::to_string(grasped[mug]) + " and released " +
           std::to_string(released[mug]) + " times (once each expected)");
  }
  // One at a time: the two carry episodes do not overlap.
  {
    int carrying = 0;
    for (const agm::GraspEvent& e : grasp_events) {
      if (e.kind == agm::GraspEvent::Kind::kGrasped && ++carrying > 1)
        fail("two objects carried at once (" + e.object + " grasped at " + fmt_s(e.t_ns) + ")");
      if (e.kind == agm::GraspEvent::Kind::kReleased) carrying = std::max(0, carrying - 1);
    }
  }
  if (s.humans && r.human_deliveries == 0) fail("no human joint pose reached the other agents");
  r.passed = r.failures.empty();
  return r;
}

}  // namespace quiver::agents::inline apps::agm
