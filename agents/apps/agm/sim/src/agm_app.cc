// The AGM app registered with the simulator: its roles, settings, shared devices, when a run is
// done, how it settles, and its figures (its checks: agm_sim_checks.cc).
#include <algorithm>
#include <memory>
#include <nlohmann/json.hpp>

#include "agm_run.h"
#include "put_back.h"
#include "quiver/agents/apps/agm/agm_schema.h"
#include "quiver/agents/apps/agm/clean_table.h"

namespace quiver::agents::inline apps::agm {
namespace internal {

AgmRun& agm_run(sim::ScenarioRun& run) { return *run.state_as<std::shared_ptr<AgmRun>>(); }

const graph::Graph& final_replica(sim::ScenarioRun& run) { return *run.host().graph(0); }

}  // namespace internal

namespace {

using internal::agm_run;
using internal::AgmRun;
using nlohmann::json;
constexpr std::int64_t kMs = 1'000'000;
constexpr std::int64_t kSec = 1'000'000'000;

// The settings of a scenario already checked (Scenario::parse() checks them first).
AgmScenario settings_of(const json& settings) {
  AgmScenario s;
  (void)internal::read_settings(settings, "", s);
  return s;
}

// The agents a mission runs, in this order: the four of the fixed route (humans unless turned
// off), the planner agent for clean-table, and the person who puts a mug back if one does.
std::vector<std::string> agents_of(const AgmScenario& s) {
  std::vector<std::string> out;
  for (const std::string& role : role_names())
    if (role != "humans" || s.humans) out.push_back(role);
  if (s.mission == kCleanTable) out.push_back(kPlannerRole);
  if (s.mission == kCleanTable && s.put_back_s > 0) out.push_back("person");
  return out;
}

const graph::Graph* planner_replica(sim::ScenarioRun& run) {
  sim::AgentHost& host = run.host();
  const int planner = host.index(kPlannerRole);
  return planner >= 0 && host.up(planner) ? host.graph(planner) : nullptr;
}

std::string plan_attr(const graph::Graph& g, const char* name) {
  const graph::NodeId plan = node_id(g, "plan");
  const graph::Value* v = plan.is_null() ? nullptr : g.attr(plan, name);
  const auto* s = v ? v->get_if<std::string>() : nullptr;
  return s ? *s : std::string();
}

// Clean-table: whether the plan is achieved on the planner's replica now (and since when).
void observe_plan(sim::ScenarioRun& run) {
  AgmRun& st = agm_run(run);
  const graph::Graph* g = planner_replica(run);
  const bool achieved = g && plan_attr(*g, "status") == "achieved";
  if (!achieved)
    st.achieved_at = -1;
  else if (st.achieved_at < 0)
    st.achieved_at = run.host().now();
}

Status start(sim::ScenarioRun& run) {
  auto st = std::make_shared<AgmRun>();
  if (Status s = internal::read_settings(run.scenario().settings, run.scenario().name, st->spec);
      !s.ok())
    return s;
  internal::read_check_params(run.scenario().checks, st->spec.checks);
  const bool clean = st->clean_table();
  // The platform outlives the navigation agent's incarnations; clean-table gives it no route.
  st->platform =
      std::make_shared<Platform>(clean ? std::vector<Leg>{} : default_route(), default_start());
  AgmRoleOptions& ro = st->roles;
  ro.platform = st->platform;
  ro.clean_table = clean;
  ro.navigation.quiet_when_done = true;
  ro.rooms.on_change = [s = st.get()](const RoomChange& c) { s->changes.push_back(c); };
  ro.grasping.on_event = [s = st.get()](const GraspEvent& e) { s->grasps.push_back(e); };
  ro.humans.rate_hz = st->spec.humans_hz;
  ro.grasping.reach_off_m = st->spec.reach_off_m;
  ro.measure_humans = st->spec.humans;
  run.state() = st;
  sim::AgentHost& host = run.host();
  host.on_agent_started([&run](int i) { agm_run(run).started_at[i] = run.host().now(); });
  // Clean-table: the plans the planner agent wrote (by version, from its replica).
  if (clean)
    host.every(10 * kMs, [&run] {
      const graph::Graph* g = planner_replica(run);
      if (!g) return;
      const graph::NodeId plan = node_id(*g, "plan");
      const graph::Value* v = plan.is_null() ? nullptr : g->attr(plan, "version");
      const std::int64_t version = v && v->get_if<std::int64_t>() ? *v->get_if<std::int64_t>() : 0;
      const std::string steps = plan_attr(*g, "steps");
      AgmRun& s = agm_run(run);
      if (version > 0 && !steps.empty() && !s.plans.count(version)) {
        s.plans[version] = steps;
        run.note("plan " + std::to_string(version) + ":\n" + steps);
      }
    });
  return {};
}

// Done once the route is over and 3 s on (clean-table: the plan achieved and the platform idle
// for 2 s).
bool done(sim::ScenarioRun& run) {
  AgmRun& st = agm_run(run);
  const std::int64_t now = run.host().now();
  if (!st.clean_table())
    return st.platform->started() && st.platform->finished(now) &&
           now > *st.platform->end_time() + 3 * kSec;
  observe_plan(run);
  return st.achieved_at >= 0 && st.platform->finished(now) && now > st.achieved_at + 2 * kSec;
}

// Heal everything, bring every agent back, quiet the trackers, let the replicas settle; then read
// the facts the checks and the figures share.
void settle(sim::ScenarioRun& run) {
  AgmRun& st = agm_run(run);
  sim::AgentHost& host = run.host();
  const Platform& p = *st.platform;
  if (st.clean_table()) {
    observe_plan(run);
    st.finished = st.achieved_at >= 0;
    st.finished_s = static_cast<double>(p.end_time().value_or(0)) / 1e9;
  } else {
    st.finished = p.finished(host.now());
    if (st.finished) st.finished_s = static_cast<double>(*p.end_time()) / 1e9;
  }
  host.heal();
  host.set_loss(0);
  for (int i = 0; i < host.size(); ++i)
    if (!host.up(i)) host.restart(i);
  host.run_until(host.now() + 2 * kSec);
  LatencyProbe pooled;
  for (int i = 0; i < host.size(); ++i) {
    const LatencyProbe* probe = nullptr;
    if (auto* a = dynamic_cast<Navigation*>(host.agent(i))) probe = &a->probe();
    if (auto* a = dynamic_cast<Rooms*>(host.agent(i))) probe = &a->probe();
    if (auto* a = dynamic_cast<Grasping*>(host.agent(i))) probe = &a->probe();
    if (probe) {
      json j;
      probe->to_json(j);
      pooled.merge_json(j);
    }
    if (auto* h = dynamic_cast<Humans*>(host.agent(i))) h->stop_tracking();
  }
  st.human_deliveries = pooled.count();
  st.human_latency_p99_ms = pooled.percentile_us(0.99) / 1e3;
  host.run_until(host.now() + 5 * kSec);

  st.converged = true;
  for (int i = 0; i < host.size(); ++i)
    if (!host.graph(i) || host.graph(i)->digest() != host.graph(0)->digest()) st.converged = false;
  const graph::Graph& g = internal::final_replica(run);
  st.expected = crossings(p, g, p.end_time().value_or(host.now()));
  if (st.clean_table()) {
    st.plan_failures = first_plan_failures(st.plans, st.plan_verified);
    if (!st.plans.empty()) {
      const std::string& first = st.plans.begin()->second;
      st.plan_steps = static_cast<int>(std::count(first.begin(), first.end(), '\n'));
    }
  }
}

void report(sim::ScenarioRun& run, json& m) {
  AgmRun& st = agm_run(run);
  const graph::Graph& g = internal::final_replica(run);
  auto room = room_of(g, node_id(g, node::kRobot));
  m["converged"] = st.converged;
  m["final_room"] = room ? g.name_of(*room) : "";
  m["room_changes"] = st.changes.size();
  m["expected_room_changes"] = st.expected.size();
  int reach_changes = 0, pauses = 0, grasps = 0, releases = 0;
  double grasped_s = -1;
  for (const GraspEvent& e : st.grasps) {
    if (e.kind == GraspEvent::Kind::kReach || e.kind == GraspEvent::Kind::kNoReach) ++reach_changes;
    if (e.kind == GraspEvent::Kind::kPaused) ++pauses;
    if (e.kind == GraspEvent::Kind::kReleased) ++releases;
    if (e.kind == GraspEvent::Kind::kGrasped) {
      ++grasps;
      grasped_s = static_cast<double>(e.t_ns) / 1e9;
    }
  }
  m["reach_changes"] = reach_changes;
  m["pauses"] = pauses;
  m["grasps"] = grasps;
  m["releases"] = releases;
  m["grasped_s"] = grasped_s;
  m["finished_s"] = st.finished_s;
  m["human_deliveries"] = st.human_deliveries;
  m["human_latency_p99_ms"] = st.human_latency_p99_ms;
  if (!st.clean_table()) return;
  const CleanTableReport rep = check_clean_table(g);
  m["mission_holds"] = rep.mission_holds;
  m["plan_status"] = rep.plan_status;
  m["plan_version"] = rep.version;
  m["replans"] = rep.replans;
  m["plan_verified"] = st.plan_verified;
  m["plan_steps"] = st.plan_steps;
}

sim::ScenarioApp make_app() {
  sim::ScenarioApp app("agm");
  app.default_agents([](const json& settings) { return agents_of(settings_of(settings)); });
  app.default_world([](const json& settings) {
    return std::string(settings_of(settings).mission == kCleanTable
                           ? embedded_file("clean-table.json")
                           : world_json());
  });
  std::vector<std::string> roles = role_names();
  roles.push_back(kPlannerRole);
  for (const std::string& role : roles)
    app.role(role, [role](sim::ScenarioRun& run) -> std::unique_ptr<Agent> {
      auto a = make_role(role, agm_run(run).roles);
      return a.ok() ? std::move(*a) : nullptr;
    });
  app.role("person", [](sim::ScenarioRun& run) -> std::unique_ptr<Agent> {
    return std::make_unique<internal::PutBack>(
        static_cast<std::int64_t>(agm_run(run).spec.put_back_s * 1e9));
  });
  app.settings([](const json& keys, const std::string& source) {
    AgmScenario s;
    return internal::read_settings(keys, source, s);
  });
  app.on_start(start);
  app.done_when(done);
  app.settle(settle);
  app.report(report);
  internal::register_checks(app);
  return app;
}

}  // namespace

const sim::ScenarioApp& agm_app() {
  static const sim::ScenarioApp app = make_app();
  return app;
}

}  // namespace quiver::agents::inline apps::agm
