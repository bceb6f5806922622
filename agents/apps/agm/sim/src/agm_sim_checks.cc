// The AGM checks by name, as scenario files turn them on: over time in the simulator and on the
// settled run (the checks of the final state: agm_checks.h, shared with the processes over DDS).
#include "agm_run.h"
#include "quiver/agents/apps/agm/agm_schema.h"
#include "quiver/agents/apps/agm/clean_table.h"

namespace quiver::agents::inline apps::agm::internal {
namespace {

using graph::NodeId;
using nlohmann::json;
using Failures = std::vector<std::string>;
constexpr std::int64_t kMs = 1'000'000;

Error bad(const std::string& where, const std::string& what) {
  return Error{ErrorCode::kInvalidArgument, where + ": " + what};
}

void append(Failures& to, const Failures& from) { to.insert(to.end(), from.begin(), from.end()); }

// A check that samples the run over time (every 10 ms of virtual time, from its start): at most
// three failures of each, reported when the run ends, with what its end adds.
class Sampled : public sim::Check {
 public:
  void start(sim::ScenarioRun& run) override {
    if (applies(agm_run(run)))
      run.host().every(10 * kMs, [this, &run] { sample(run, agm_run(run)); });
  }
  void finish(sim::ScenarioRun& run, Failures& f) override {
    append(f, failures_);
    at_end(run, agm_run(run), f);
  }

 protected:
  virtual bool applies(const AgmRun&) const { return true; }
  virtual void sample(sim::ScenarioRun& run, AgmRun& st) = 0;
  virtual void at_end(sim::ScenarioRun&, AgmRun&, Failures&) {}
  void fail(const std::string& what) {
    if (failures_.size() < 3) failures_.push_back(what);
  }

 private:
  Failures failures_;
};

// movedInLastSeconds on the navigation agent's replica matches the odometry (the fixed route),
// once its incarnation has run for 200 ms and the truth has not just changed.
class MovedMatchesOdometry final : public Sampled {
  bool applies(const AgmRun& st) const override { return !st.clean_table(); }
  void sample(sim::ScenarioRun& run, AgmRun& st) override {
    sim::AgentHost& host = run.host();
    const int nav = host.index("navigation");
    const std::int64_t t = host.now(), window = st.roles.navigation.moved_window_ns;
    if (nav < 0 || !host.up(nav) || !host.runtime(nav) || !st.started_at.count(nav) ||
        t - st.started_at[nav] <= 200 * kMs)
      return;
    const graph::Graph& g = *host.graph(nav);
    const NodeId robot = node_id(g, node::kRobot);
    const bool truth = st.platform->moved_between(t - window, t);
    const bool settled = truth == st.platform->moved_between(t - 40 * kMs - window, t - 40 * kMs);
    if (!robot.is_null() && settled && g.has_edge(robot, robot, edge::kMoved) != truth)
      fail("at " + seconds_text(t) + " movedInLastSeconds is " + (truth ? "absent" : "present") +
           " on navigation's replica, odometry says " + (truth ? "moved" : "still"));
  }
};

// Never grasping while the platform drives: over time on the grasping agent's replica (a grasp
// still announced `motion_allowance_ms` after a drive began), and at the end over the grasps
// completed and the objects put down.
class NoGraspWhileDriving final : public Sampled {
  static std::int64_t allowance(const AgmRun& st) {
    return static_cast<std::int64_t>(st.spec.checks.motion_allowance_ms * 1e6);
  }
  void sample(sim::ScenarioRun& run, AgmRun& st) override {
    sim::AgentHost& host = run.host();
    const int grasping = host.index("grasping");
    if (grasping < 0 || !host.up(grasping) || !host.graph(grasping)) return;
    const std::int64_t t = host.now();
    std::int64_t began = -1;
    for (auto [b, e] : st.platform->drives())
      if (b <= t && t < e) began = b;
    const graph::Graph& g = *host.graph(grasping);
    const NodeId robot = node_id(g, node::kRobot);
    if (!robot.is_null() && began >= 0 && t - began > allowance(st) &&
        !g.edges_from(robot, edge::kGrasping).empty())
      fail("at " + seconds_text(t) + " still grasping, the platform drives since " +
           seconds_text(began));
  }
  void at_end(sim::ScenarioRun&, AgmRun& st, Failures& f) override {
    append(f, grasp_motion_failures(st.grasps, *st.platform, allowance(st),
                                    st.roles.navigation.moved_window_ns));
  }
};

template <class C>
sim::ScenarioApp::CheckFactory sampled() {
  return [](const json& p, const std::string& where) -> Result<std::unique_ptr<sim::Check>> {
    if (!p.is_boolean()) return bad(where, "expected true or false");
    if (!p.get<bool>()) return std::unique_ptr<sim::Check>();
    return std::unique_ptr<sim::Check>(std::make_unique<C>());
  };
}

// A check on the settled run: `fn(run, state, failures)`.
template <class Fn>
sim::ScenarioApp::CheckFactory at_end(Fn fn) {
  return sim::switch_check([fn](sim::ScenarioRun& run, Failures& f) { fn(run, agm_run(run), f); });
}

// A parameter of other checks (read from the scenario's checks when a run starts): checked here,
// it checks nothing by itself.
sim::ScenarioApp::CheckFactory flag_parameter() {
  return [](const json& p, const std::string& where) -> Result<std::unique_ptr<sim::Check>> {
    if (!p.is_boolean()) return bad(where, "expected true or false");
    return std::unique_ptr<sim::Check>();
  };
}

sim::ScenarioApp::CheckFactory ms_parameter() {
  return [](const json& p, const std::string& where) -> Result<std::unique_ptr<sim::Check>> {
    if (!p.is_number() || p.get<double>() <= 0 || p.get<double>() > 60'000)
      return bad(where, "expected milliseconds in (0, 60000]");
    return std::unique_ptr<sim::Check>();
  };
}

// Clean-table is exact (once per crossing, each mug once) only without faults and without a mug
// put back.
bool undisturbed(sim::ScenarioRun& run, const AgmRun& st) {
  return run.scenario().faults.empty() && st.spec.put_back_s <= 0;
}

}  // namespace

void register_checks(sim::ScenarioApp& app) {
  app.check("exact_crossings", flag_parameter());
  app.check("crossing_lag_ms", ms_parameter());
  app.check("motion_allowance_ms", ms_parameter());
  app.check("moved_matches_odometry", sampled<MovedMatchesOdometry>());
  app.check("no_grasp_while_driving", sampled<NoGraspWhileDriving>());
  app.check("finished", at_end([](sim::ScenarioRun& run, AgmRun& st, Failures& f) {
              if (st.finished) return;
              const std::string limit = std::to_string(run.scenario().limit_s);
              f.push_back(st.clean_table() ? "the plan was not achieved within " + limit + " s"
                                           : "the route did not end within " + limit +
                                                 " s (the platform waits for the grasp)");
            }));
  app.check("converged", at_end([](sim::ScenarioRun&, AgmRun& st, Failures& f) {
              if (!st.converged) f.push_back("replicas differ after healing and 5 s of quiet");
            }));
  app.check("end_state", at_end([](sim::ScenarioRun& run, AgmRun& st, Failures& f) {
              append(f, end_state_failures(final_replica(run), st.spec.mission));
            }));
  app.check("room_changes", at_end([](sim::ScenarioRun& run, AgmRun& st, Failures& f) {
              if (st.clean_table()) {
                append(f, crossing_count_failures(st.changes, st.expected,
                                                  run.scenario().faults.empty()));
                return;
              }
              const bool exact = st.spec.checks.exact_crossings;
              const auto frame = static_cast<std::int64_t>(1e9 / st.roles.navigation.rate_hz);
              append(f, room_change_failures(final_replica(run), *st.platform, st.changes, exact,
                                             st.spec.checks.crossing_lag_ms, frame));
              append(f, crossing_count_failures(st.changes, st.expected, exact));
            }));
  app.check("reach", at_end([](sim::ScenarioRun&, AgmRun& st, Failures& f) {
              const double on = st.roles.grasping.reach_on_m;
              if (!st.clean_table()) {
                append(f, reach_failures(st.grasps, *st.platform, on, false));
                return;
              }
              for (const GraspEvent& e : st.grasps)
                if (e.kind == GraspEvent::Kind::kReach && e.distance >= on)
                  f.push_back("reach of " + e.object + " set at FCL distance " +
                              std::to_string(e.distance));
            }));
  app.check("grasps", at_end([](sim::ScenarioRun& run, AgmRun& st, Failures& f) {
              if (st.clean_table()) {
                append(f, carry_failures(st.grasps, undisturbed(run, st)));
                return;
              }
              int grasps = 0;
              for (const GraspEvent& e : st.grasps) grasps += e.kind == GraspEvent::Kind::kGrasped;
              if (grasps == 0) f.push_back("the mug was never grasped");
              if (st.spec.checks.exact_crossings && grasps != 1)
                f.push_back("grasped " + std::to_string(grasps) + " times");
            }));
  app.check("expect_pause", at_end([](sim::ScenarioRun&, AgmRun& st, Failures& f) {
              bool paused = false;
              for (const GraspEvent& e : st.grasps)
                paused = paused || e.kind == GraspEvent::Kind::kPaused;
              if (!st.clean_table() && !paused)
                f.push_back("the nudge mid-grasp did not pause the grasp");
            }));
  app.check("human_poses_delivered", at_end([](sim::ScenarioRun&, AgmRun& st, Failures& f) {
              if (st.spec.humans && st.human_deliveries == 0)
                f.push_back("no human joint pose reached the other agents");
            }));
  // Clean-table: the first plan through the grammar guard, and replanning when (and only when)
  // the world deviates.
  app.check(
      "plan", at_end([](sim::ScenarioRun& run, AgmRun& st, Failures& f) {
        if (!st.clean_table()) return;
        append(f, st.plan_failures);
        const std::int64_t replans = check_clean_table(final_replica(run)).replans;
        if (st.spec.put_back_s > 0 && replans < 1)
          f.push_back("the mug was put back on the table, yet the planner never replanned");
        if (undisturbed(run, st) && replans != 0)
          f.push_back("the planner replanned " + std::to_string(replans) + " times without faults");
      }));
}

}  // namespace quiver::agents::inline apps::agm::internal
