// quiver scenario agm (the AGM scenarios of seed 001 — navigation, robot-in-room, grasping and
// human tracking — one process per agent over DDS on loopback, checked from an observer replica)
// and quiver bench humans (the human-tracking load reaching the other agents while they work):
// their options; the runs are agents/apps/agm/process's.
#include <cstdio>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "dds_options.h"
#include "quiver/agents/apps/agm/agm_roles.h"
#include "quiver/agents/apps/agm/agm_schema.h"
#include "quiver/agents/apps/agm/custody.h"
#include "quiver/agents/apps/agm/team_world.h"
#include "quiver/agents/apps/agm/process/agm_runs.h"
#include "quiver/agents/apps/agm/process/team_run.h"
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
  // One line per grasp event and per drive, flushed at once (the team scenario reads them, also
  // from a process killed with SIGKILL).
  auto say = [](const nlohmann::json& j) {
    std::printf("%s\n", j.dump().c_str());
    std::fflush(stdout);
  };
  if (!f.team_robot.empty()) {
    for (const agm::TeamRobot& r : agm::team_robots(f.robots))
      if (r.tag == f.team_robot) ro.team = r;
    if (!ro.team) {
      agents::named_logger("quiver run")->error("--team-robot {}: a team of {} robots has robots A to {}", f.team_robot,
                                                f.robots, std::string(1, static_cast<char>('A' + f.robots - 1)));
      return 2;
    }
    ro.team_size = f.robots;
    ro.navigation.resume_from_graph = true;
    ro.navigation.on_drive = [say](std::int64_t b, std::int64_t e) { say({{"drive", {{"begin_ns", b}, {"end_ns", e}}}}); };
    ro.grasping.on_event = [say](const agm::GraspEvent& e) {
      say({{"grasp_event", {{"kind", e.name()}, {"object", e.object}, {"t_ns", e.t_ns}}}});
    };
    if (!f.custody.empty()) {
      auto c = agm::FileCustody::open(f.custody);
      if (!c.ok()) {
        agents::named_logger("quiver run")->error("{}", c.error().to_string());
        return 2;
      }
      ro.grasping.custody = std::move(*c);
    }
  }
  auto agent = agm::make_role(f.role, ro);
  if (!agent.ok()) {
    agents::named_logger("quiver run")->error("{}", agent.error().to_string());
    return 2;
  }
  if (f.process.world.empty() && ro.team)
    f.process.world_text = *agm::team_world_json(f.robots);
  else if (f.process.world.empty())
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
    run->add_option("--team-robot", f.team_robot,
                    "AGM in a team (docs/teams.md): the robot this agent works for (A, B, ...): its nodes, its plan, the team's world")
        ->check(CLI::IsMember({"A", "B", "C", "D", "E", "F", "G", "H"}));
    run->add_option("--robots", f.robots, "AGM in a team: how many robots it has")
        ->check(CLI::Range(2, agm::kMaxTeamRobots))
        ->capture_default_str();
    run->add_option("--custody", f.custody,
                    "AGM grasping in a team: the directory through which the robots' hands hold the objects (one hand each)");
  };
  return r;
}

// quiver scenario team: robots as network namespaces with real processes (root).
void add_team_scenario(CLI::App* scenario) {
  auto t = std::make_shared<agm::TeamDdsRun>();
  auto* c = scenario->add_subcommand(
      "team", "The team scenario in seed 001's world (docs/teams.md): robots as network namespaces (root), each with its "
              "gateway and agents; the team link cut and healed, a robot crashed and restarted from its stores; checked");
  c->add_option("--robots", t->robots, "robots (A, B, ...)")->check(CLI::Range(2, agm::kMaxTeamRobots))->capture_default_str();
  c->add_option("--agents-per-robot", t->agents_per_robot,
                "processes per robot, its gateway included (navigation, rooms, grasping, planner, the human tracker on "
                "robot A, then idle agents)")
      ->check(CLI::Range(6, 29))
      ->capture_default_str();
  c->add_option("--partition-at", t->partition_at_s, "cut the team link this many seconds after the start")
      ->check(CLI::Range(0.0, 3600.0))
      ->capture_default_str();
  c->add_option("--heal-at", t->heal_at_s, "heal it this many seconds after the start")
      ->check(CLI::Range(0.0, 3600.0))
      ->capture_default_str();
  auto no_cut = std::make_shared<bool>(false);
  c->add_flag("--no-partition", *no_cut, "never cut the team link");
  c->add_option("--crash", t->crash, "ROBOT@S: SIGKILL of all of that robot's processes S seconds after the start, "
                                     "restarted from their stores 2 s later (\"\": no crash)")
      ->capture_default_str();
  c->add_option("--limit", t->limit_s, "give up after this many seconds")->check(CLI::Range(10.0, 3600.0))->capture_default_str();
  c->add_option("--out", t->out, "keep the logs, stores and final graph here (default: a new /tmp/quiver-team-*)");
  c->callback([t, no_cut] {
    if (*no_cut) t->partition_at_s = -1;
    if (t->partition_at_s >= 0 && t->heal_at_s <= t->partition_at_s) {
      agents::named_logger("quiver scenario team")->error("--heal-at {} must come after --partition-at {}", t->heal_at_s, t->partition_at_s);
      set_exit_code(2);
      return;
    }
    if (!t->crash.empty()) {
      const auto at = t->crash.find('@');
      const std::string robot = t->crash.substr(0, at);
      if (at == std::string::npos || robot.size() != 1 || robot[0] < 'A' || robot[0] >= 'A' + t->robots) {
        agents::named_logger("quiver scenario team")
            ->error("--crash {}: expected ROBOT@SECONDS with a robot from A to {}", t->crash,
                    std::string(1, static_cast<char>('A' + t->robots - 1)));
        set_exit_code(2);
        return;
      }
    }
    set_exit_code(agm::run_team_over_dds(*t));
  });
}

void add_agm_commands(CLI::App& app) {
  add_team_scenario(app.get_subcommand("scenario"));
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
