// The Barthel commands: run ROLE (one Barthel agent, or one of ExtraRoles, as this process),
// scenario barthel and bench reaction (agents/apps/barthel/process runs them). In `quiver` and
// in the lean quiver-barthel.
#include <nlohmann/json.hpp>

#include "commands.h"
#include "quiver/agents/runtime/process/logging.h"
#include "dds_options.h"
#include "run_flags.h"
#include "quiver/agents/apps/barthel/grammars.h"
#include "quiver/agents/apps/barthel/barthel_roles.h"
#include "quiver/agents/apps/barthel/process/barthel_runs.h"

namespace quiver::tools {
namespace {

namespace barthel = agents::barthel;
using nlohmann::json;

int run_role(RunFlags f, const ExtraRoles& extra) {
  if (extra.has && extra.has(f.role)) return extra.run(std::move(f));
  barthel::RoleOptions ro;
  ro.out_dir = f.out;
  ro.name = f.name;
  ro.simulated_speech = f.simulated_speech;
  ro.sim_ns_per_word = static_cast<std::int64_t>(f.words_ms * 1e6);
  ro.planner.answer_timeout_ns = static_cast<std::int64_t>(f.answer_timeout_s * 1e9);
  if (!f.script.empty()) {
    auto s = barthel::PatientScript::load(f.script);
    if (!s.ok()) {
      agents::named_logger("quiver run")->error("{}", s.error().to_string());
      return 2;
    }
    ro.script = *s;
  } else {
    ro.script = barthel::PatientScript::random(f.patient_seed);
  }
  auto agent = barthel::make_role(f.role, ro);
  if (!agent.ok()) {
    if (extra.names.empty()) agents::named_logger("quiver run")->error("{}", agent.error().to_string());
    else agents::named_logger("quiver run")->error("{}; {}", agent.error().to_string(), extra.names);
    return 2;
  }
  if (f.process.world.empty()) f.process.world_text = std::string(barthel::world_json());
  return agents::run_process(**agent, f.process);
}

struct ScenarioFlags {
  DdsFlags dds;
  barthel::BarthelDdsRun run;
};

struct ReactionFlags {
  DdsFlags dds;
  barthel::ReactionBench bench;
};

// The DDS flags as a process run's options: the domain, the configuration, this executable to
// start the agents with, and the observer's replica.
void apply(const DdsFlags& dds, barthel::BarthelProcessOptions& p, agents::ReplicaFactory& observer) {
  p.domain = dds.domain;
  p.dds_config = dds.dds_config;
  p.exe = agents::sibling_or_self("quiver-barthel");  // the lean one when it is built beside
  observer = [dds](agents::DdsReplicaOptions o) { return dds.create_agent(std::move(o)); };
}

}  // namespace

void add_barthel_commands(CLI::App& app, const ExtraRoles& extra) {
  auto rf = std::make_shared<RunFlags>();
  auto* run = app.add_subcommand("run", extra.has ? "Run one agent of the Barthel test or of the AGM scenarios as this process (over DDS)"
                                                  : "Run one agent of the Barthel test as this process (over DDS)");
  run->add_option("role", rf->role, "Barthel: planner | speech | panel | person | patient" + extra.help)->required();
  rf->process.add_all(run);
  run->add_option("--out", rf->out, "real devices write here (WAVs, screen PNGs, result.json); none: simulated devices");
  run->add_option("--name", rf->name, "the agent's name (default: the role; a second planner needs another)");
  run->add_option("--script", rf->script, "patient: the script (JSON) it follows")->check(CLI::ExistingFile);
  run->add_option("--patient-seed", rf->patient_seed, "patient: draw a cooperative script from this seed")
      ->check(CLI::NonNegativeNumber);
  run->add_flag("--simulated-speech", rf->simulated_speech, "speech: simulated durations instead of espeak-ng");
  run->add_option("--words-ms", rf->words_ms, "simulated speech: milliseconds per word")->check(CLI::Range(1.0, 5000.0));
  run->add_option("--answer-timeout", rf->answer_timeout_s, "planner: seconds to wait for an answer")
      ->check(CLI::Range(0.1, 600.0));
  if (extra.add_options) extra.add_options(run, *rf);
  run->callback([rf, extra] { set_exit_code(run_role(*rf, extra)); });

  auto sf = std::make_shared<ScenarioFlags>();
  auto* sc = app.add_subcommand("scenario", "Run a scenario as one process per agent over DDS on loopback");
  auto* b = sc->add_subcommand("barthel", "The Barthel test: five agent processes, a live transcript from the graph");
  sf->dds.add_to(b);
  b->add_option("--out", sf->run.out, "output folder (default: a new /tmp/quiver-barthel-*)");
  b->add_option("--script", sf->run.script, "the patient's script (JSON; default: the demo patient)")->check(CLI::ExistingFile);
  b->add_option("--kill", sf->run.kill, "kill -9 this agent mid-test and restart it (\"\" for none)");
  b->add_option("--kill-at-item", sf->run.kill_at_item, "... when the test reaches this item")->check(CLI::Range(0, 9));
  b->add_option("--restart-after", sf->run.restart_after_s, "... and restart it this many seconds later")->check(CLI::Range(0.0, 60.0));
  b->add_option("--timeout", sf->run.timeout_s, "give up after this many seconds")->check(CLI::Range(1.0, 86400.0));
  b->add_option("--answer-timeout", sf->run.processes.answer_timeout_s, "seconds the planner waits for an answer")->check(CLI::Range(0.1, 600.0));
  b->add_option("--words-ms", sf->run.processes.words_ms, "simulated speech: milliseconds per word")->check(CLI::Range(1.0, 5000.0));
  b->add_flag("--simulated-speech", sf->run.processes.simulated_speech, "simulated speech durations instead of espeak-ng (faster)");
  b->add_option("--never-speaking-absent-ms", sf->run.never_speaking_absent_ms,
                "check: never speaking to the patient longer than this after the person left")->check(CLI::Range(1.0, 600000.0));
  b->add_flag("--expect-interruption", sf->run.expect_interruption, "check: the person's leaving stops the robot mid-sentence at least once");
  b->add_flag("--second-planner", sf->run.second_planner, "start a second planner instance too (it waits; it takes over if needed)");
  b->callback([sf] {
    barthel::BarthelDdsRun run = sf->run;
    apply(sf->dds, run.processes, run.observer);
    set_exit_code(barthel::run_barthel_over_dds(run));
  });
}

void add_reaction_bench_command(CLI::App& app) {
  CLI::App* bench = app.get_subcommand("bench");
  auto f = std::make_shared<ReactionFlags>();
  f->dds.domain = 81;
  barthel::ReactionBench& b = f->bench;
  b.processes.words_ms = 60;
  auto* r = bench->add_subcommand("reaction",
                                  "Person lost -> Speech stops the audio: the Barthel agents as processes over DDS (loopback)");
  f->dds.add_to(r);
  r->add_option("--leaves", b.leaves, "times the patient leaves mid-question per run")->check(CLI::Range(1, 100'000))->capture_default_str();
  r->add_option("--runs", b.runs, "runs (the summary gives the median of their percentiles)")->check(CLI::Range(1, 1000))->capture_default_str();
  r->add_option("--words-ms", b.processes.words_ms, "simulated speech: milliseconds per word")->check(CLI::Range(1.0, 5000.0))->capture_default_str();
  r->add_option("--leave-after-ms", b.leave_after_ms, "the patient leaves this long into the question")->check(CLI::Range(1.0, 60000.0))->capture_default_str();
  r->add_option("--away-ms", b.away_ms, "and comes back this much later")->check(CLI::Range(1.0, 60000.0))->capture_default_str();
  r->add_option("--out", b.out, "keep each run's logs, script and result in OUT/run-K (default: new /tmp folders)");
  r->callback([f] {
    barthel::ReactionBench run = f->bench;
    apply(f->dds, run.processes, run.observer);
    set_exit_code(barthel::run_reaction_bench(run));
  });
}

}  // namespace quiver::tools
