// quiver run ROLE (one Barthel agent as a process) and quiver scenario barthel (all of them, one
// process each, over DDS on loopback, with a live transcript read from the graph).
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "quiver/agents/runtime/process/logging.h"
#include "dds_options.h"
#include "quiver/agents/apps/agm/agm_roles.h"
#include "quiver/agents/apps/agm/agm_schema.h"
#include "quiver/agents/apps/barthel/checks.h"
#include "quiver/agents/apps/barthel/grammars.h"
#include "quiver/agents/apps/barthel/barthel_roles.h"
#include "quiver/agents/apps/barthel/transcript.h"
#include "quiver/agents/devices/json_result_store.h"
#include "barthel_processes.h"

namespace quiver::tools {
namespace {

namespace barthel = agents::barthel;
using nlohmann::json;

struct RunFlags {
  agents::ProcessFlags process;
  std::string role, out, script, name;
  std::uint64_t patient_seed = 1;
  bool simulated_speech = false;
  double answer_timeout_s = 8;
  double words_ms = 250;
  bool measure_humans = false;
  bool quiet_when_done = false;
  std::string mission;
};

Result<barthel::PatientScript> load_script(const std::string& path) {
  std::ifstream in(path);
  if (!in) return Error{ErrorCode::kIo, path + ": cannot open the patient script"};
  try {
    auto s = barthel::PatientScript::from_json(json::parse(in));
    if (!s.ok()) return Error{s.error().code, path + ":" + s.error().message};
    return s;
  } catch (const json::parse_error& e) {
    return Error{ErrorCode::kInvalidArgument, path + ": not JSON: " + e.what()};
  }
}

// One agent of the AGM scenarios (agents/apps/agm), on the AGM world unless told otherwise.
int run_agm_role(RunFlags f) {
  agents::agm::AgmRoleOptions ro;
  ro.name = f.name;
  ro.measure_humans = f.measure_humans;
  ro.navigation.quiet_when_done = f.quiet_when_done;
  ro.clean_table = f.mission == agents::agm::kCleanTable;
  auto agent = agents::agm::make_role(f.role, ro);
  if (!agent.ok()) {
    agents::named_logger("quiver run")->error("{}", agent.error().to_string());
    return 2;
  }
  if (f.process.world.empty())
    f.process.world_text = std::string(ro.clean_table || f.role == agents::agm::kPlannerRole
                                           ? agents::agm::embedded_file("clean-table.json")
                                           : agents::agm::world_json());
  return agents::run_process(**agent, f.process);
}

int run_role(RunFlags f) {
  if (agents::agm::is_role_or_planner(f.role)) return run_agm_role(std::move(f));
  barthel::RoleOptions ro;
  ro.out_dir = f.out;
  ro.name = f.name;
  ro.simulated_speech = f.simulated_speech;
  ro.sim_ns_per_word = static_cast<std::int64_t>(f.words_ms * 1e6);
  ro.planner.answer_timeout_ns = static_cast<std::int64_t>(f.answer_timeout_s * 1e9);
  if (!f.script.empty()) {
    auto s = load_script(f.script);
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
    std::string agm_roles;
    for (const auto& r : agents::agm::role_names()) agm_roles += (agm_roles.empty() ? "" : ", ") + r;
    agents::named_logger("quiver run")->error("{}; AGM roles: {}", agent.error().to_string(), agm_roles);
    return 2;
  }
  if (f.process.world.empty()) f.process.world_text = std::string(barthel::world_json());
  return agents::run_process(**agent, f.process);
}

struct ScenarioFlags {
  DdsFlags dds;
  std::string out, script, kill = "planner";
  int kill_at_item = 4;
  double restart_after_s = 1.0;
  double timeout_s = 600;
  bool simulated_speech = false;
  bool second_planner = false;
  double answer_timeout_s = 8;
  double words_ms = 250;
  double never_speaking_absent_ms = 300;
  bool expect_interruption = false;
};

// The demo's patient: answers by voice, once stays silent and then touches the screen, once
// says something the robot cannot understand, and leaves the chair in the middle of a question.
barthel::PatientScript demo_script() {
  using barthel::ReplyKind;
  barthel::PatientScript s = barthel::PatientScript::random(7);
  s.items[1].first = {ReplyKind::kSilent, 0};
  s.items[1].second = {ReplyKind::kTouch, 1};
  s.items[3].first = {ReplyKind::kMisunderstand, 0};
  s.items[3].second = {ReplyKind::kVoice, 2};
  s.leaves.push_back({2, 1'500'000'000, 4'000'000'000});
  return s;
}

int run_barthel(const ScenarioFlags& f) {
  std::string out = f.out;
  if (out.empty()) {
    char tmpl[] = "/tmp/quiver-barthel-XXXXXX";
    if (!mkdtemp(tmpl)) {
      std::perror("quiver scenario: mkdtemp");
      return 2;
    }
    out = tmpl;
  }
  ::mkdir(out.c_str(), 0755);
  barthel::PatientScript script = demo_script();
  if (!f.script.empty()) {
    auto s = load_script(f.script);
    if (!s.ok()) {
      agents::named_logger("quiver scenario")->error("{}", s.error().to_string());
      return 2;
    }
    script = *s;
  }
  const std::string script_path = out + "/patient.json";
  std::ofstream(script_path) << script.to_json().dump(1) << "\n";

  BarthelProcesses procs({f.dds.domain, f.dds.dds_config, out, script_path, f.answer_timeout_s, f.simulated_speech, f.words_ms});
  agents::DdsReplicaOptions o;
  o.name = "transcript";
  o.observer = true;
  auto created = f.dds.create_agent(o);
  if (!created.ok()) {
    agents::named_logger("quiver scenario")->error("{}", created.error().to_string());
    return 2;
  }
  agents::DdsReplica& obs = **created;
  const auto t0 = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  barthel::Transcript transcript(obs.graph(), [&](const std::string& line) {
    std::printf("[%6.1f s] %s\n", elapsed(), line.c_str());
    std::fflush(stdout);
  });
  // Checked over time from this replica: never speaking to the patient while the person is away.
  barthel::AbsenceWatch absence;
  auto sample = [&] {
    absence.sample(agents::monotonic_ns(), barthel::patient_present_truth(obs.graph()), barthel::speaking_to_patient(obs.graph()));
  };
  obs.graph().subscribe([&](const graph::ChangeBatch& b) {
    transcript.on_changes(b);
    sample();
  });

  std::printf("Barthel test over Cyclone DDS (domain %u, loopback): planner, speech, panel, person and the simulated "
              "patient, one process each, no executive.\nOutput folder: %s\n\n",
              f.dds.domain, out.c_str());
  for (const auto& r : barthel::role_names())
    if (!procs.start(r)) {
      agents::named_logger("quiver scenario")->error("cannot start {} run {}", self_executable(), r);
      return 2;
    }
  if (f.second_planner) procs.start("planner", "planner-2");

  bool killed = false, restarted = false;
  double killed_at = 0, final_at = -1;
  while (elapsed() < f.timeout_s) {
    obs.spin_once(20'000'000);
    sample();
    if (!f.kill.empty() && !killed && transcript.item() >= f.kill_at_item) {
      const int pid = procs.kill(f.kill, SIGKILL);
      if (pid > 0) {
        std::printf("[%6.1f s] *** kill -9 %s (pid %d) during item %d\n", elapsed(), f.kill.c_str(), pid, transcript.item());
        killed = true;
        killed_at = elapsed();
      }
    }
    if (killed && !restarted && elapsed() - killed_at >= f.restart_after_s) {
      procs.start(f.kill);
      std::printf("[%6.1f s] *** %s restarted (empty replica; it continues from what the graph holds)\n", elapsed(),
                  f.kill.c_str());
      restarted = true;
    }
    const bool final = transcript.status() == "done" || transcript.status() == "clinician_called";
    if (final && final_at < 0) final_at = elapsed();
    if (final && (transcript.goodbye_said() || elapsed() - final_at > 30)) break;
  }
  procs.stop_all();

  // The result the clinician validates, against what the patient's script implies; the checks.
  std::vector<std::string> failures;
  const auto expected = script.expected();
  std::printf("\nResult (%s/result.json): ", out.c_str());
  auto result = agents::devices::load_test_result(out + "/result.json");
  if (!result.ok()) {
    std::printf("none stored\n");
    failures.push_back(result.error().to_string());
  } else {
    std::printf("%s, %d of 100 (the patient's script implies %s, %d)\n", result->status.c_str(), result->total,
                expected.status.c_str(), expected.total);
    for (auto& d : barthel::result_differences(*result, expected)) failures.push_back(d);
  }
  for (auto& d : barthel::questions_asked_twice(obs.graph())) failures.push_back(d);
  if (absence.max_ms() > f.never_speaking_absent_ms)
  {
    char why[160];
    std::snprintf(why, sizeof why, "spoke to the patient %.1f ms after the person had left (limit %.0f ms)", absence.max_ms(),
                  f.never_speaking_absent_ms);
    failures.push_back(why);
  }
  if (f.expect_interruption && transcript.interruptions() == 0)
    failures.push_back("the person left but the robot was never stopped mid-sentence");
  std::printf("Checks: every item's score as the script implies, no question asked twice, never speaking to the "
              "patient more than %.0f ms after the person left (longest: %.0f ms), %d sentence(s) stopped mid-way.\n",
              f.never_speaking_absent_ms, absence.max_ms(), transcript.interruptions());
  for (const auto& d : failures) std::printf("  FAILED: %s\n", d.c_str());
  std::printf(failures.empty() ? "The stored result matches the patient's script.\n"
                               : "The run FAILED its checks.\n");
  std::printf("Audio: %s/speech/*.wav   Screens: %s/screen/*.png   Pages: %s/pages.jsonl   Logs: %s/logs/\n",
              out.c_str(), out.c_str(), out.c_str(), out.c_str());
  return failures.empty() ? 0 : 1;
}

}  // namespace

void add_barthel_commands(CLI::App& app) {
  auto rf = std::make_shared<RunFlags>();
  auto* run = app.add_subcommand("run", "Run one agent of the Barthel test or of the AGM scenarios as this process (over DDS)");
  run->add_option("role", rf->role,
                  "Barthel: planner | speech | panel | person | patient; AGM: navigation | rooms | grasping | humans | agm-planner")
      ->required();
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
  run->add_flag("--measure-humans", rf->measure_humans,
                "AGM navigation, rooms, grasping, agm-planner: measure how fresh the human joints are when they arrive (status line)");
  run->add_flag("--quiet-when-done", rf->quiet_when_done, "AGM navigation: stop publishing once the route is done");
  run->add_option("--mission", rf->mission,
                  "AGM: clean-table (its world; navigation and grasping follow the plan agm-planner writes)")
      ->check(CLI::IsMember({"", "clean-table"}));
  run->callback([rf] { set_exit_code(run_role(*rf)); });

  auto sf = std::make_shared<ScenarioFlags>();
  auto* sc = app.add_subcommand("scenario", "Run a scenario as one process per agent over DDS on loopback");
  auto* b = sc->add_subcommand("barthel", "The Barthel test: five agent processes, a live transcript from the graph");
  sf->dds.add_to(b);
  b->add_option("--out", sf->out, "output folder (default: a new /tmp/quiver-barthel-*)");
  b->add_option("--script", sf->script, "the patient's script (JSON; default: the demo patient)")->check(CLI::ExistingFile);
  b->add_option("--kill", sf->kill, "kill -9 this agent mid-test and restart it (\"\" for none)");
  b->add_option("--kill-at-item", sf->kill_at_item, "... when the test reaches this item")->check(CLI::Range(0, 9));
  b->add_option("--restart-after", sf->restart_after_s, "... and restart it this many seconds later")->check(CLI::Range(0.0, 60.0));
  b->add_option("--timeout", sf->timeout_s, "give up after this many seconds")->check(CLI::Range(1.0, 86400.0));
  b->add_option("--answer-timeout", sf->answer_timeout_s, "seconds the planner waits for an answer")->check(CLI::Range(0.1, 600.0));
  b->add_option("--words-ms", sf->words_ms, "simulated speech: milliseconds per word")->check(CLI::Range(1.0, 5000.0));
  b->add_flag("--simulated-speech", sf->simulated_speech, "simulated speech durations instead of espeak-ng (faster)");
  b->add_option("--never-speaking-absent-ms", sf->never_speaking_absent_ms,
                "check: never speaking to the patient longer than this after the person left")->check(CLI::Range(1.0, 600000.0));
  b->add_flag("--expect-interruption", sf->expect_interruption, "check: the person's leaving stops the robot mid-sentence at least once");
  b->add_flag("--second-planner", sf->second_planner, "start a second planner instance too (it waits; it takes over if needed)");
  b->callback([sf] { set_exit_code(run_barthel(*sf)); });
}

}  // namespace quiver::tools
