// quiver scenario agm (the AGM scenarios of seed 001 — navigation, robot-in-room, grasping and
// human tracking — one process per agent over DDS on loopback, checked from an observer replica)
// and quiver bench humans (the human-tracking load reaching the other agents while they work):
// their options; the runs are agents/apps/agm/process's.
#include "commands.h"
#include "dds_options.h"
#include "quiver/agents/apps/agm/agm_roles.h"
#include "quiver/agents/apps/agm/process/agm_runs.h"

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

struct ScenarioFlags {
  DdsFlags dds;
  std::string out;
  agm::AgmDdsRun run;
};

struct BenchFlags {
  DdsFlags dds;
  std::string out;
  agm::HumansBench bench;
};

}  // namespace

void add_agm_commands(CLI::App& app) {
  auto sf = std::make_shared<ScenarioFlags>();
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

  auto bf = std::make_shared<BenchFlags>();
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
