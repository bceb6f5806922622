#pragma once
/// @file
/// What a Barthel run is checked against, the same in both hosts (the simulator and the DDS
/// processes): the stored result against the patient's script, no question asked twice, and
/// never speaking to the patient while the person has been away too long.
#include <cstdint>
#include <string>
#include <vector>

#include "quiver/agents/apps/barthel/patient_script.h"
#include "quiver/agents/devices/result_store.h"
#include "quiver/graph/graph.h"

namespace quiver::agents::inline apps::barthel {

/// How `r` differs from what the script implies: status, total and each item's score, an item
/// missing (skipped) or extra. Empty when they agree.
std::vector<std::string> result_differences(const devices::TestResult& r, const PatientScript::Outcome& expected);

/// Each question (item, attempt) the speaker said to the end more than once, read from a replica
/// that saw the whole test: "item 3 attempt 1 asked 2 times". Empty when none.
std::vector<std::string> questions_asked_twice(const graph::Graph& g);

/// Whether the simulated patient is in the chair (the ground truth it writes, not the sensor's).
bool patient_present_truth(const graph::Graph& g);
/// Whether the speaker's `speaking` mark is on an utterance meant for the patient (calling the
/// patient back is said to the room and does not count).
bool speaking_to_patient(const graph::Graph& g);

/// The longest time the robot spoke to the patient after the person had left: feed it samples.
class AbsenceWatch {
 public:
  /// At `now`: whether the person is present and whether the robot is speaking to them.
  void sample(std::int64_t now, bool present, bool speaking);
  double max_ms() const { return max_ms_; }

 private:
  std::int64_t absent_since_ = -1;
  double max_ms_ = 0;
};

}  // namespace quiver::agents::inline apps::barthel
