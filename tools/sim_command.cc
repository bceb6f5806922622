// quiver sim: the options of a simulated run (Barthel, AGM, a scenario file or random schedules).
#include <algorithm>
#include <cstdio>
#include <iostream>
#include <sstream>

#include "commands.h"
#include "progress.h"
#include "quiver/agents/runtime/process/logging.h"
#include <nlohmann/json.hpp>

#include "quiver/agents/apps/agm/sim/agm_scenario.h"
#include "quiver/agents/apps/agm/sim/team_scenario.h"
#include "quiver/agents/apps/agm/team_world.h"
#include "quiver/agents/apps/barthel/sim/barthel_scenario.h"
#include "quiver/base/rng.h"
#include "quiver/sim/simulator.h"

namespace quiver::tools {
namespace {

// `quiver sim --team R --schedules N`: N seeded runs (seeds --seed ..), each with the agents on R
// robots, loss up to 30% on every network (at least --team-loss on the team's), the team network
// partitioned, agents and gateways killed and restarted, agents competing for locks. A run passes
// when every replica (agents and both sides of every gateway) converges with no invariant
// violation, rejected sample or lock held by two agents that could hear each other.
int run_team_schedules(const sim::SimConfig& base, int n, std::function<void(std::int64_t, const std::string&)> log) {
  int failed = 0;
  ProgressLine progress("team schedules", n);
  for (int k = 0; k < n; ++k) {
    sim::SimConfig c = base;
    c.seed = base.seed + static_cast<std::uint64_t>(k);
    Rng draw(c.seed ^ 0x7ea3);
    c.faults.loss = draw.below(31) / 100.0;
    c.faults.reorder = draw.chance(0.5);
    c.faults.partitions = true;
    c.faults.crashes = true;
    c.locks.enabled = true;
    c.log = log;
    sim::SimResult r = sim::run_simulation(c);
    if (!r.ok()) ++failed;
    progress.update(k + 1, std::to_string(failed) + " failed");
    if (!r.ok() || n == 1) {
      progress.clear();
      nlohmann::json j = nlohmann::json::parse(r.to_json());
      j["loss"] = c.faults.loss;
      if (!r.ok())
        j["replay"] = "quiver sim --team " + std::to_string(c.team.robots) + " --agents " + std::to_string(c.agents) +
                      " --steps " + std::to_string(c.steps) + " --schedules 1 --seed " + std::to_string(c.seed);
      std::cout << j.dump() << std::endl;
    }
  }
  progress.finish();
  std::cout << nlohmann::json{{"team_schedules", n}, {"passed", n - failed}, {"failed", failed}, {"first_seed", base.seed},
                              {"robots", base.team.robots}, {"agents", base.agents}}
                   .dump()
            << std::endl;
  return failed ? 1 : 0;
}

// The team scenario in seed 001's world (`--agm --team R`): one run without faults, or N seeded
// random schedules (team link cuts, robot and gateway crashes, loss on the team network).
int run_agm_team(int robots, int agents_per_robot, double humans_hz, std::uint64_t first_seed, int schedules,
                 std::function<void(std::int64_t, const std::string&)> log) {
  const int n = std::max(1, schedules);
  int failed = 0;
  ProgressLine progress("team schedules", n);
  for (int k = 0; k < n; ++k) {
    const std::uint64_t seed = first_seed + static_cast<std::uint64_t>(k);
    agents::agm::TeamScenario s = schedules > 0 ? agents::agm::TeamScenario::random_faults(seed, robots, agents_per_robot)
                                                : agents::agm::TeamScenario{};
    s.robots = robots;
    s.agents_per_robot = agents_per_robot;
    s.humans_hz = humans_hz;
    agents::agm::TeamResult r = agents::agm::run_team_scenario(s, seed, log);
    if (!r.passed) ++failed;
    progress.update(k + 1, std::to_string(failed) + " failed");
    if (!r.passed || n == 1) {
      progress.clear();
      nlohmann::json j = r.to_json();
      if (!r.passed) {
        std::ostringstream replay;
        replay << "quiver sim --agm --team " << robots << " --agents-per-robot " << agents_per_robot << " --humans-hz "
               << humans_hz << (schedules > 0 ? " --schedules 1" : "") << " --seed " << seed;
        j["replay"] = replay.str();
      }
      std::cout << j.dump() << std::endl;
    }
  }
  progress.finish();
  if (n > 1)
    std::cout << nlohmann::json{{"agm_team_schedules", n}, {"passed", n - failed}, {"failed", failed}, {"first_seed", first_seed},
                                {"robots", robots}, {"agents_per_robot", agents_per_robot}}
                     .dump()
              << std::endl;
  return failed ? 1 : 0;
}

}  // namespace

void add_sim_command(CLI::App& app) {
  auto cfg = std::make_shared<sim::SimConfig>();
  auto* cmd = app.add_subcommand("sim", "Run many replicas in one process on a seeded virtual network with faults");
  cmd->add_option("--agents", cfg->agents, "number of agents (replicas)")->check(CLI::Range(1, 1000))->capture_default_str();
  cmd->add_option("--steps", cfg->steps, "workload transactions")->check(CLI::Range(0, 10'000'000))->capture_default_str();
  cmd->add_option("--seed", cfg->seed, "seed: a seed replays exactly")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_option("--loss", cfg->faults.loss, "probability a frame is lost")->check(CLI::Range(0.0, 0.95));
  cmd->add_option("--dup", cfg->faults.dup, "probability a frame is duplicated")->check(CLI::Range(0.0, 1.0));
  cmd->add_flag("--reorder", cfg->faults.reorder, "let frames overtake each other");
  cmd->add_flag("--partitions", cfg->faults.partitions, "split the agents into groups for a while, then heal");
  cmd->add_flag("--crashes", cfg->faults.crashes, "kill agents (state lost) and restart them");
  cmd->add_flag("--locks", cfg->locks.enabled, "agents also compete for priority locks on a few scopes");
  cmd->add_flag("--rooms", cfg->rooms.enabled, "agents move a robot between rooms under a grammar (violations repaired)");
  auto protocol = std::make_shared<std::string>("gossip");
  cmd->add_option("--protocol", *protocol,
                  "membership and anti-entropy: gossip (constant-size beats to one peer per period) or all-to-all "
                  "(every replica's whole (origin, seq) set to every peer each heartbeat: the protocol before issue 22)")
      ->check(CLI::IsMember({"gossip", "all-to-all"}))
      ->capture_default_str();
  cmd->add_flag("--split", cfg->split_until_end,
                "split the agents into two halves from a fifth of the workload to its end (settle_ms: converging after the heal)");
  cmd->add_option("--team", cfg->team.robots,
                  "robots: split the agents over this many robots, each its own network with a gateway, joined by a "
                  "slower, lossier team network (docs/teams.md); with --schedules N, N random team fault schedules; "
                  "with --agm, the team scenario (robots fetching the mugs together)")
      ->check(CLI::Range(2, 16));
  cmd->add_option("--team-loss", cfg->team.loss, "the team network's loss while faults run")
      ->check(CLI::Range(0.0, 0.95))
      ->capture_default_str();
  auto verbose = std::make_shared<bool>(false);
  cmd->add_flag("-v,--verbose", *verbose, "narrate faults and phases on stderr");
  auto scenario = std::make_shared<std::string>();
  auto schedules = std::make_shared<int>(0);
  cmd->add_option("--scenario", *scenario,
                  "run a Barthel scenario file (agents, patient, faults, checks) instead; with --agm, an AGM one")
      ->check(CLI::ExistingFile);
  cmd->add_option("--schedules", *schedules,
                  "run N random fault schedules of the Barthel scenario (seeds --seed .. --seed+N-1)")
      ->check(CLI::Range(1, 1'000'000));
  auto agm = std::make_shared<bool>(false);
  cmd->add_flag("--agm", *agm,
                "the AGM scenarios (navigation, rooms, grasping, humans): one run without faults, or with --schedules N "
                "random fault schedules");
  auto mission = std::make_shared<std::string>();
  cmd->add_option("--mission", *mission,
                  "with --agm: clean-table (the planner agent plans, navigation and grasping follow its plan: both mugs "
                  "from the table to the kitchen)")
      ->check(CLI::IsMember({"", "clean-table"}));
  auto per_robot = std::make_shared<int>(6);
  cmd->add_option("--agents-per-robot", *per_robot,
                  "with --agm --team R: processes per robot, its gateway included (navigation, rooms, grasping, planner, "
                  "the human tracker on robot A, then idle agents)")
      ->check(CLI::Range(6, 29))
      ->capture_default_str();
  auto humans_hz = std::make_shared<double>(30);
  cmd->add_option("--humans-hz", *humans_hz, "with --agm --team R: the tracker's frame rate (2 people x 15 joints)")
      ->check(CLI::Range(1.0, 120.0))
      ->capture_default_str();
  cmd->callback([cfg, verbose, scenario, schedules, agm, mission, protocol, per_robot, humans_hz] {
    cfg->replicator.gossip = *protocol == "gossip";
    auto log = agents::named_logger("quiver sim");
    auto narrate = [log](std::int64_t t, const std::string& line) { log->info("[{:8.3f} s] {}", static_cast<double>(t) / 1e9, line); };
    if (*agm && cfg->team.robots >= 2) {
      if (cfg->team.robots > agents::agm::kMaxTeamRobots) {
        log->error("--agm --team takes 2 to {} robots, not {}", agents::agm::kMaxTeamRobots, cfg->team.robots);
        set_exit_code(2);
        return;
      }
      set_exit_code(run_agm_team(cfg->team.robots, *per_robot, *humans_hz, cfg->seed, *schedules,
                                 *verbose ? narrate : std::function<void(std::int64_t, const std::string&)>{}));
      return;
    }
    if (*agm) {
      const int n = scenario->empty() ? std::max(1, *schedules) : 1;
      int failed = 0;
      ProgressLine progress("schedules", n);
      for (int k = 0; k < n; ++k) {
        const std::uint64_t seed = cfg->seed + static_cast<std::uint64_t>(k);
        agents::agm::AgmScenario s = *schedules > 0 ? agents::agm::AgmScenario::random_faults(seed, *mission) : agents::agm::AgmScenario{};
        if (*schedules == 0 && !mission->empty()) {
          s.name = *mission;
          s.mission = *mission;
        }
        if (!scenario->empty()) {
          auto loaded = agents::agm::AgmScenario::load(*scenario);
          if (!loaded.ok()) {
            log->error("{}", loaded.error().to_string());
            set_exit_code(2);
            return;
          }
          s = *loaded;
        }
        if (*verbose) log->info("AGM scenario {}, seed {}", s.name, seed);
        agents::agm::AgmResult r = agents::agm::run_agm_scenario(s, seed, *verbose ? narrate : std::function<void(std::int64_t, const std::string&)>{});
        if (!r.passed) ++failed;
        progress.update(k + 1, std::to_string(failed) + " failed");
        if (!r.passed || n == 1) {
          progress.clear();
          nlohmann::json j = r.to_json();
          if (!r.passed)
            j["replay"] = std::string("quiver sim --agm ") + (scenario->empty() ? "" : "--scenario " + *scenario + " ") +
                          (mission->empty() || !scenario->empty() ? "" : "--mission " + *mission + " ") +
                          (*schedules > 0 ? "--schedules 1 " : "") + "--seed " + std::to_string(seed);
          std::cout << j.dump() << std::endl;
        }
      }
      progress.finish();
      if (n > 1)
        std::cout << nlohmann::json{{"agm_schedules", n}, {"passed", n - failed}, {"failed", failed}, {"first_seed", cfg->seed}}.dump()
                  << std::endl;
      set_exit_code(failed ? 1 : 0);
      return;
    }
    if (cfg->team.robots >= 2 && *schedules > 0) {
      set_exit_code(run_team_schedules(*cfg, *schedules, *verbose ? narrate : std::function<void(std::int64_t, const std::string&)>{}));
      return;
    }
    if (!scenario->empty() || *schedules > 0) {
      std::vector<std::pair<agents::barthel::BarthelScenario, std::uint64_t>> runs;
      if (!scenario->empty()) {
        auto s = agents::barthel::BarthelScenario::load(*scenario);
        if (!s.ok()) {
          agents::named_logger("quiver sim")->error("{}", s.error().to_string());
          set_exit_code(2);
          return;
        }
        runs.emplace_back(*s, cfg->seed);
      }
      for (int k = 0; k < *schedules; ++k) runs.emplace_back(agents::barthel::BarthelScenario::random_faults(cfg->seed + k), cfg->seed + k);
      int failed = 0;
      ProgressLine progress("schedules", static_cast<long>(runs.size()));
      long done = 0;
      for (auto& [s, seed] : runs) {
        if (*verbose) log->info("scenario {}, seed {}", s.name, seed);
        agents::barthel::BarthelResult r = agents::barthel::run_scenario(s, seed, *verbose ? narrate : std::function<void(std::int64_t, const std::string&)>{});
        if (!r.passed) ++failed;
        progress.update(++done, std::to_string(failed) + " failed");
        if (!r.passed || runs.size() == 1) {
          progress.clear();
          nlohmann::json j = r.to_json();
          if (!r.passed) j["replay"] = scenario->empty() ? "quiver sim --schedules 1 --seed " + std::to_string(seed) : "quiver sim --scenario " + *scenario + " --seed " + std::to_string(seed);
          std::cout << j.dump() << std::endl;
        }
      }
      progress.finish();
      if (runs.size() > 1)
        std::cout << nlohmann::json{{"schedules", runs.size()}, {"passed", runs.size() - static_cast<std::size_t>(failed)}, {"failed", failed}, {"first_seed", cfg->seed}}.dump() << std::endl;
      set_exit_code(failed ? 1 : 0);
      return;
    }
    if (*verbose) cfg->log = narrate;
    ProgressLine progress("steps", cfg->steps);
    cfg->progress = [&progress](int done, int) { progress.update(done); };
    log->info("seed {}, {} agents, {} steps (replay with --seed {})", cfg->seed, cfg->agents, cfg->steps, cfg->seed);
    sim::SimResult r = sim::run_simulation(*cfg);
    cfg->progress = nullptr;
    progress.finish();
    std::cout << r.to_json() << std::endl;
    set_exit_code(r.ok() ? 0 : 1);
  });
}

}  // namespace quiver::tools
