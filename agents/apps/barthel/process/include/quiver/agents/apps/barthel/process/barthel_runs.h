#pragma once
/// @file
/// The Barthel test over DDS, one process per agent (BarthelProcesses), watched from an observer
/// replica that prints a live transcript read from the graph and checks at the end the stored
/// result against the patient's script, no question asked twice and never speaking to an absent
/// patient: `quiver scenario barthel`. And the reaction benchmark (`quiver bench reaction`): how
/// fast Speech stops talking when the person leaves.
#include <string>

#include "quiver/agents/apps/barthel/patient_script.h"
#include "quiver/agents/apps/barthel/process/barthel_processes.h"
#include "quiver/agents/runtime/process/dds_replica.h"

namespace quiver::agents::inline apps::barthel {

/// The demo's patient: answers by voice, once stays silent and then touches the screen, once
/// says something the robot cannot understand, and leaves the chair in the middle of a question.
PatientScript demo_script();

struct BarthelDdsRun {
  /// The domain, configuration and executable; the answer timeout and simulated speech. The run
  /// sets `out` (from `out` below) and `script_path` (it writes the script there).
  BarthelProcessOptions processes;
  ReplicaFactory observer;    ///< opens the observer's replica
  std::string out;            ///< output folder; empty: a new /tmp/quiver-barthel-*
  std::string script;         ///< the patient's script (JSON file); empty: demo_script()
  std::string kill = "planner";  ///< kill -9 this agent mid-test and restart it ("": none)
  int kill_at_item = 4;          ///< ... when the test reaches this item
  double restart_after_s = 1.0;  ///< ... and restart it this much later
  double timeout_s = 600;        ///< give up after this
  bool second_planner = false;   ///< a second planner instance too (it waits; it takes over)
  double never_speaking_absent_ms = 300;  ///< check: longest speech to an absent patient
  bool expect_interruption = false;       ///< check: a sentence is stopped mid-way at least once
};

/// Runs it. @returns the exit status: 0 when every check holds, 1 when one fails, 2 when it
/// cannot start (the reason logged).
int run_barthel_over_dds(const BarthelDdsRun& r);

struct ReactionBench {
  /// The domain, configuration, executable and words_ms; the bench sets the rest per run.
  BarthelProcessOptions processes;
  ReplicaFactory observer;  ///< opens the observer's replica
  int leaves = 100;         ///< times the patient leaves mid-question per run
  int runs = 3;
  double leave_after_ms = 300;  ///< the patient leaves this long into the question
  double away_ms = 400;         ///< and comes back this much later
  std::string out;  ///< keep each run in OUT/run-K (default: new /tmp folders)
};

/// Person lost -> Speech stops the audio, `runs` times: one JSON line per run (p50/p99/max ms of
/// the reactions Speech measured) and one of the medians on stdout. @returns 0, or 1 when a run
/// measured nothing.
int run_reaction_bench(const ReactionBench& b);

}  // namespace quiver::agents::inline apps::barthel
