// Clean the table over DDS (`quiver scenario agm --mission clean-table`): the planner agent as a
// fifth process, navigation and grasping following its plan, watched from the observer's replica
// and checked at the end: the mission holds, the plan is achieved and its first version replays
// through the grammar guard, each mug grasped and released once, one at a time, replicas equal.
#include <cstdio>

#include "observed_run.h"
#include "quiver/agents/apps/agm/agm_checks.h"
#include "quiver/agents/apps/agm/agm_roles.h"
#include "quiver/agents/apps/agm/agm_schema.h"
#include "quiver/agents/apps/agm/clean_table.h"
#include "quiver/agents/apps/agm/latency_probe.h"
#include "quiver/agents/runtime/process/logging.h"

namespace quiver::agents::inline apps::agm::internal {
namespace {

using graph::NodeId;
using json = nlohmann::json;

// What the observer sees: the plans by version, the objects carried and put down, the room
// changes, the plan's progress.
struct CleanTableSeen {
  std::map<std::int64_t, std::string> plans;
  std::vector<GraspEvent> carried;  ///< kGrasped, kReleased
  int room_changes = 0;
  std::string last_next;

  void on_edge(ObservedRun& run, const graph::Graph& g, const graph::EdgeChange& e) {
    const std::string type(e.key.type.str()), to = g.name_of(e.key.to);
    const bool made = e.kind == graph::ChangeKind::kCreated,
               gone = e.kind == graph::ChangeKind::kDeleted;
    if (type == edge::kIn && made && g.edge_attr(e.key, "committed_ns")) {
      ++room_changes;
      run.say("changeRoom -> " + to);
    } else if (type == edge::kReach && made && g.edge_attr(e.key, "distance")) {
      run.say("reach " + to);
    } else if (type == edge::kCarrying && (made || gone)) {
      GraspEvent c;
      c.kind = made ? GraspEvent::Kind::kGrasped : GraspEvent::Kind::kReleased;
      c.object = to;
      c.t_ns = monotonic_ns();
      carried.push_back(c);
      run.say(made ? "grasped " + to + " (off the table)" : "released " + to);
    }
  }

  void on_plan(ObservedRun& run, const graph::Graph& g) {
    const NodeId plan = node_id(g, "plan");
    if (plan.is_null()) return;
    auto v = g.get<std::int64_t>(plan, "version");
    auto steps = g.get<std::string>(plan, "steps");
    if (v.ok() && steps.ok() && !steps->empty() && !plans.count(*v)) {
      plans[*v] = *steps;
      run.say("plan " + std::to_string(*v) + " written by the planner agent:\n" + *steps);
    }
    auto status = g.get<std::string>(plan, "status");
    auto next = g.get<std::int64_t>(plan, "next");
    const std::string now_next =
        (status.ok() ? *status : "") + " " + (next.ok() ? std::to_string(*next + 1) : "");
    if (now_next == last_next) return;
    last_next = now_next;
    if (auto st = next_plan_step(g))
      run.say("plan: next step " + std::to_string(st->index + 1) + " (" + st->rule + ")");
    else if (status.ok())
      run.say("plan: " + *status);
  }

  int count(GraspEvent::Kind kind, const char* object) const {
    int n = 0;
    for (const GraspEvent& e : carried) n += e.kind == kind && e.object == object;
    return n;
  }
};

}  // namespace

int run_clean_table(const AgmDdsRun& r) {
  if (!r.kill.empty()) {
    // A navigation process restarted mid-mission would start a new platform at the start pose.
    named_logger("quiver scenario")
        ->error("--kill is not supported with --mission clean-table (docs/scenarios.md, limits)");
    return 2;
  }
  auto opened = ObservedRun::open(r, "quiver-agm-clean-table", embedded_file("clean-table.json"));
  if (!opened) return 2;
  ObservedRun& run = *opened;
  graph::Graph& g = run.graph();
  CleanTableSeen seen;
  run.watch([&](NodeId, const graph::EdgeChange& e) { seen.on_edge(run, g, e); },
            [&] { seen.on_plan(run, g); });
  const std::vector<std::string> mission = {"--mission", kCleanTable},
                                 measured = {"--measure-humans", "--mission", kCleanTable};
  if (!run.start(
          "Clean the table", "the planner agent, navigation, rooms, grasping and humans",
          {{"navigation", {"--measure-humans", "--quiet-when-done", "--mission", kCleanTable}},
           {"rooms", measured},
           {"grasping", measured},
           {kPlannerRole, measured},
           {"humans", mission}}))
    return 2;
  std::vector<std::string> failures;
  const std::int64_t deadline = run.started_ns() + static_cast<std::int64_t>(r.timeout_s * 1e9);
  std::int64_t achieved_at = -1;
  while (monotonic_ns() < deadline) {
    run.replica().spin_once(20 * kMs);
    const NodeId plan = node_id(g, "plan"), robot = node_id(g, node::kRobot);
    auto status = plan.is_null() ? Result<std::string>(make_error(ErrorCode::kNotFound, "plan"))
                                 : g.get<std::string>(plan, "status");
    if (!status.ok() || *status != "achieved") {
      achieved_at = -1;
      continue;
    }
    if (achieved_at < 0) achieved_at = monotonic_ns();
    if (!robot.is_null() && !g.has_edge(robot, robot, edge::kMoved) &&
        monotonic_ns() > achieved_at + 2 * kSec)
      break;
  }
  if (achieved_at < 0)
    failures.push_back("the plan was not achieved within " + std::to_string(r.timeout_s) + " s");

  std::optional<json> humans;
  std::map<std::string, json> finals =
      run.stop({"navigation", "rooms", "grasping", kPlannerRole}, humans);

  // Checks: those of the simulator on what the observer saw, and the processes' own.
  append(failures, end_state_failures(g, kCleanTable));
  std::string verified = "no plan";
  append(failures, first_plan_failures(seen.plans, verified));
  append(failures, carry_failures(seen.carried, true));
  const std::string digest = g.digest().hex();
  bool equal = false;
  append(failures, final_status_failures(finals, digest, 4, humans, equal));
  LatencyProbe pooled;
  for (const auto& [role, st] : finals)
    if (st.contains("humans_latency")) pooled.merge_json(st["humans_latency"]);
  const CleanTableReport rep = check_clean_table(g);
  std::printf(
      "\nChecks: mission %s on the final replica; plan '%s' (version %lld, %lld replans), its "
      "first version through "
      "the grammar guard: %s; %d changeRoom; mugs grasped/released %d/%d and %d/%d; human joints "
      "reached the others: "
      "p50 %.0f us, p99 %.0f us (%llu poses); replicas %s.\n",
      rep.mission_holds ? "holds" : "does NOT hold", rep.plan_status.c_str(),
      static_cast<long long>(rep.version), static_cast<long long>(rep.replans), verified.c_str(),
      seen.room_changes, seen.count(GraspEvent::Kind::kGrasped, "mug"),
      seen.count(GraspEvent::Kind::kReleased, "mug"),
      seen.count(GraspEvent::Kind::kGrasped, "mug2"),
      seen.count(GraspEvent::Kind::kReleased, "mug2"), pooled.percentile_us(0.5),
      pooled.percentile_us(0.99), static_cast<unsigned long long>(pooled.count()),
      (equal ? "all equal (digest " + digest.substr(0, 12) + ")" : std::string("NOT equal"))
          .c_str());
  return ObservedRun::verdict(failures, "The mission holds; the run passed its checks.");
}

}  // namespace quiver::agents::inline apps::agm::internal
