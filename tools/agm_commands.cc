// quiver scenario agm (the AGM scenarios of seed 001 — navigation, robot-in-room, grasping and
// human tracking — one process per agent over DDS on loopback, checked from an observer replica)
// and quiver bench humans (the human-tracking load reaching the other agents while they work):
// their options; the runs are agents/apps/agm/process's.
#include "commands.h"
#include "dds_options.h"
#include "quiver/agents/apps/agm/agm_roles.h"
#include "quiver/agents/apps/agm/agm_schema.h"
#include "quiver/agents/apps/agm/process/agm_runs.h"
#include "quiver/agents/runtime/process/logging.h"
#include "run_flags.h"

namespace quiver::tools {
namespace {

namespace agm = agents::agm;

// The processes' options from the DDS flags: this executable runs each agent.
agm::AgmProcessOptions processes(const DdsFlags& dds, const std::string& out) {
  agm::AgmProcessOptions o;
  o.dds = dds;
  o.exe = agents::self_executable();
  o.out = out;
  return o;
}

// One agent of the AGM scenarios (agents/apps/agm), on the AGM world unless told otherwise.
int run_agm_role(RunFlags f) {
  agm::AgmRoleOptions ro;
  ro.name = f.name;
  ro.measure_humans = f.measure_humans;
  ro.navigation.quiet_when_done = f.quiet_when_done;
  ro.clean_table = f.mission == agm::kCleanTable;
  auto agent = agm::make_role(f.role, ro);
  if (!agent.ok()) {
    agents::named_logger("quiver run")->error("{}", agent.error().to_string());
    return 2;
  }
  if (f.process.world.empty())
    f.process.world_text = std::string(ro.clean_table || f.role == agm::kPlannerRole ? agm::embedded_file("clean-table.json")
                                                                                     : agm::world_json());
  return agents::run_process(**agent, f.process);
}

struct AgmScenarioFlags {
  DdsFlags dds;
  std::string out;
  agm::AgmDdsRun run;
};

struct HumansBenchFlags {
  DdsFlags dds;
  std::string out;
  agm::HumansBench bench;
};

}  // namespace

ExtraRoles agm_roles() {
  ExtraRoles r;
  r.help = "; AGM: navigation | rooms | grasping | humans | agm-planner";
  for (const auto& name : agm::role_names()) r.names += (r.names.empty() ? "AGM roles: " : ", ") + name;
  r.has = [](const std::string& role) { return agm::is_role_or_planner(role); };
  r.run = run_agm_role;
  r.add_options = [](CLI::App* run, RunFlags& f) {
    run->add_flag("--measure-humans", f.measure_humans,
                  "AGM navigation, rooms, grasping, agm-planner: measure how fresh the human joints are when they arrive (status line)");
    run->add_flag("--quiet-when-done", f.quiet_when_done, "AGM navigation: stop publishing once the route is done");
    run->add_option("--mission", f.mission, "AGM: clean-table (its world; navigation and grasping follow the plan agm-planner writes)")
        ->check(CLI::IsMember({"", "clean-table"}));
  };
  return r;
}

void add_agm_commands(CLI::App& app) {
  auto sf = std::make_shared<AgmScenarioFlags>();
  sf->dds.domain = 48;
  agm::AgmDdsRun& r = sf->run;
  CLI::App* scenario = app.get_subcommand("scenario");
  auto* a = scenario->add_subcommand(
      "agm",
      "The AGM scenarios (seed 001): navigation, robot-in-room, grasping, human "
      "tracking; one process each");
  sf->dds.add_to(a);
  a->add_option("--out", sf->out, "logs go to OUT/logs (default: a new /tmp/quiver-agm-*)");
  a->add_option("--timeout", r.timeout_s, "give up after this many seconds")
      ->check(CLI::Range(1.0, 86400.0))
      ->capture_default_str();
  a->add_option("--crossing-lag-ms", r.crossing_lag_ms,
                "check: changeRoom committed within this of the pose past the limit")
      ->check(CLI::Range(1.0, 10000.0))
      ->capture_default_str();
  a->add_option("--motion-allowance-ms", r.motion_allowance_ms,
                "check: a grasp ends within this of the platform moving")
      ->check(CLI::Range(1.0, 10000.0))
      ->capture_default_str();
  a->add_option("--kill", r.kill,
                "kill -9 this agent (navigation, rooms, grasping, humans) mid-run and restart it")
      ->check(CLI::IsMember(agm::role_names()));
  a->add_option("--mission", r.mission,
                "clean-table: the planner agent runs too (a fifth process) and navigation and "
                "grasping follow its "
                "plan: both mugs from the table to the kitchen")
      ->check(CLI::IsMember({"", "clean-table"}));
  a->add_option("--kill-at", r.kill_at_s, "... this many seconds after the start")
      ->check(CLI::Range(0.0, 3600.0))
      ->capture_default_str();
  a->add_option("--restart-after", r.restart_after_s, "... and restart it this many seconds later")
      ->check(CLI::Range(0.0, 600.0))
      ->capture_default_str();
  a->callback([sf] {
    agm::AgmDdsRun run = sf->run;
    run.processes = processes(sf->dds, sf->out);
    run.observer = [dds = sf->dds](agents::DdsReplicaOptions o) {
      return dds.create_agent(std::move(o));
    };
    set_exit_code(agm::run_agm_over_dds(run));
  });

  auto bf = std::make_shared<HumansBenchFlags>();
  bf->dds.domain = 49;
  agm::HumansBench& b = bf->bench;
  CLI::App* bench = app.get_subcommand("bench");
  auto* h = bench->add_subcommand(
      "humans",
      "Human tracking (2 people x 15 joints x 30 Hz) reaching the navigation, rooms and "
      "grasping agents while they work: latency p50/p99/max, rate");
  bf->dds.add_to(h);
  h->add_option("--seconds", b.seconds, "how long the tracker runs")
      ->check(CLI::Range(1.0, 3600.0))
      ->capture_default_str();
  h->add_option("--max-p99-ms", b.max_p99_ms, "exit 1 when the p99 latency exceeds this")
      ->check(CLI::Range(0.01, 10000.0))
      ->capture_default_str();
  h->add_flag("--no-planner", b.no_planner,
              "without the planner agent: the fixed route (default: the clean-the-table mission, "
              "the planner agent "
              "planning and tracking, navigation and grasping following it)");
  h->add_option("--out", bf->out,
                "logs go to OUT/logs (default: a new /tmp/quiver-bench-humans-*)");
  h->callback([bf] {
    agm::HumansBench run = bf->bench;
    run.processes = processes(bf->dds, bf->out);
    set_exit_code(agm::run_humans_bench(run));
  });
}

}  // namespace quiver::tools
