// quiver scenario barthel: the Barthel agents as processes, a live transcript and the checks.
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <fstream>

#include "quiver/agents/apps/barthel/checks.h"
#include "quiver/agents/apps/barthel/grammars.h"
#include "quiver/agents/apps/barthel/barthel_roles.h"
#include "quiver/agents/apps/barthel/process/barthel_runs.h"
#include "quiver/agents/apps/barthel/transcript.h"
#include "quiver/agents/devices/json_result_store.h"
#include "quiver/agents/runtime/process/logging.h"
#include "quiver/agents/runtime/process/observer_replica.h"

namespace quiver::agents::inline apps::barthel {
namespace {

// The result the clinician validates against what the patient's script implies, and the checks
// made from the observer's replica. @returns the failures.
std::vector<std::string> check_run(const BarthelDdsRun& r, const std::string& out,
                                   const PatientScript& script, const graph::Graph& g,
                                   const AbsenceWatch& absence, const Transcript& transcript) {
  std::vector<std::string> failures;
  const auto expected = script.expected();
  std::printf("\nResult (%s/result.json): ", out.c_str());
  auto result = devices::load_test_result(out + "/result.json");
  if (!result.ok()) {
    std::printf("none stored\n");
    failures.push_back(result.error().to_string());
  } else {
    std::printf("%s, %d of 100 (the patient's script implies %s, %d)\n", result->status.c_str(),
                result->total, expected.status.c_str(), expected.total);
    for (auto& d : result_differences(*result, expected)) failures.push_back(d);
  }
  for (auto& d : questions_asked_twice(g)) failures.push_back(d);
  if (absence.max_ms() > r.never_speaking_absent_ms) {
    char why[160];
    std::snprintf(why, sizeof why,
                  "spoke to the patient %.1f ms after the person had left (limit %.0f ms)",
                  absence.max_ms(), r.never_speaking_absent_ms);
    failures.push_back(why);
  }
  if (r.expect_interruption && transcript.interruptions() == 0)
    failures.push_back("the person left but the robot was never stopped mid-sentence");
  std::printf(
      "Checks: every item's score as the script implies, no question asked twice, never speaking "
      "to the patient more than %.0f ms after the person left (longest: %.0f ms), %d sentence(s) "
      "stopped mid-way.\n",
      r.never_speaking_absent_ms, absence.max_ms(), transcript.interruptions());
  return failures;
}

}  // namespace

PatientScript demo_script() {
  PatientScript s = PatientScript::random(7);
  s.items[1].first = {ReplyKind::kSilent, 0};
  s.items[1].second = {ReplyKind::kTouch, 1};
  s.items[3].first = {ReplyKind::kMisunderstand, 0};
  s.items[3].second = {ReplyKind::kVoice, 2};
  s.leaves.push_back({2, 1'500'000'000, 4'000'000'000});
  return s;
}

int run_barthel_over_dds(const BarthelDdsRun& r) {
  auto log = named_logger("quiver scenario");
  const std::string out = out_dir(r.out, "quiver-barthel");
  PatientScript script = demo_script();
  if (!r.script.empty()) {
    auto s = PatientScript::load(r.script);
    if (!s.ok()) {
      log->error("{}", s.error().to_string());
      return 2;
    }
    script = *s;
  }
  BarthelProcessOptions po = r.processes;
  po.out = out;
  po.script_path = out + "/patient.json";
  BarthelProcesses procs(po);  // makes `out`
  std::ofstream(po.script_path) << script.to_json().dump(1) << "\n";

  auto observer = open_observer_replica(r.observer, "transcript", "quiver scenario", world_json());
  if (!observer) return 2;
  DdsReplica& obs = *observer;
  const auto t0 = std::chrono::steady_clock::now();
  auto elapsed = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  Transcript transcript(obs.graph(), [&](const std::string& line) {
    std::printf("[%6.1f s] %s\n", elapsed(), line.c_str());
    std::fflush(stdout);
  });
  // Checked over time from this replica: never speaking to the patient while the person is away.
  AbsenceWatch absence;
  auto sample = [&] {
    absence.sample(monotonic_ns(), patient_present_truth(obs.graph()),
                   speaking_to_patient(obs.graph()));
  };
  obs.graph().subscribe([&](const graph::ChangeBatch& b) {
    transcript.on_changes(b);
    sample();
  });

  std::printf(
      "Barthel test over Cyclone DDS (domain %u, loopback): planner, speech, panel, person and "
      "the simulated patient, one process each, no executive.\nOutput folder: %s\n\n",
      po.domain, out.c_str());
  for (const auto& role : role_names())
    if (!procs.start(role)) {
      log->error("cannot start {} run {}", po.exe, role);
      return 2;
    }
  if (r.second_planner) procs.start("planner", "planner-2");

  bool killed = false, restarted = false;
  double killed_at = 0, final_at = -1;
  while (elapsed() < r.timeout_s) {
    obs.spin_once(20'000'000);
    sample();
    if (!r.kill.empty() && !killed && transcript.item() >= r.kill_at_item) {
      const int pid = procs.kill(r.kill, SIGKILL);
      if (pid > 0) {
        std::printf("[%6.1f s] *** kill -9 %s (pid %d) during item %d\n", elapsed(),
                    r.kill.c_str(), pid, transcript.item());
        killed = true;
        killed_at = elapsed();
      }
    }
    if (killed && !restarted && elapsed() - killed_at >= r.restart_after_s) {
      procs.start(r.kill);
      std::printf(
          "[%6.1f s] *** %s restarted (empty replica; it continues from what the graph holds)\n",
          elapsed(), r.kill.c_str());
      restarted = true;
    }
    const bool final = transcript.status() == "done" || transcript.status() == "clinician_called";
    if (final && final_at < 0) final_at = elapsed();
    if (final && (transcript.goodbye_said() || elapsed() - final_at > 30)) break;
  }
  procs.stop_all();

  const std::vector<std::string> failures =
      check_run(r, out, script, obs.graph(), absence, transcript);
  for (const auto& d : failures) std::printf("  FAILED: %s\n", d.c_str());
  std::printf(failures.empty() ? "The stored result matches the patient's script.\n"
                               : "The run FAILED its checks.\n");
  std::printf(
      "Audio: %s/speech/*.wav   Screens: %s/screen/*.png   Pages: %s/pages.jsonl   Logs: "
      "%s/logs/\n",
      out.c_str(), out.c_str(), out.c_str(), out.c_str());
  return failures.empty() ? 0 : 1;
}

}  // namespace quiver::agents::inline apps::barthel
