#pragma once
/// @file
/// The robot's sensors of the patient, behind small interfaces: speech recognition (what the
/// patient said), the touchscreen's touches, and the person sensor (presence; the joints' poses
/// come from the sensor's body model). The simulated implementations read the simulated
/// patient's ground truth: the attributes of the `sim_patient` node, which the Patient agent
/// writes. In a process that is the agent's own replica; in the simulator the host hands the
/// Patient agent's replica (the world's truth, not delayed by the network).
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "quiver/graph/graph.h"

namespace quiver::agents::inline apps::barthel {

/// Something the patient said. `seq` grows with each utterance; `for_seq` is the prompt it answers.
struct Heard {
  std::int64_t seq = 0;
  std::string text;
  std::int64_t for_seq = -1;
};

/// A touch on an option of the screen showing prompt `for_seq`.
struct Touch {
  std::int64_t seq = 0;
  int option = -1;
  std::int64_t for_seq = -1;
};

class SpeechInput {
 public:
  virtual ~SpeechInput() = default;
  /// The latest recognised utterance, if any.
  virtual std::optional<Heard> last(const graph::Graph& own) = 0;
};

class TouchInput {
 public:
  virtual ~TouchInput() = default;
  virtual std::optional<Touch> last(const graph::Graph& own) = 0;
};

class PersonSensor {
 public:
  virtual ~PersonSensor() = default;
  /// Is someone sitting in front of the robot? nullopt: no reading.
  virtual std::optional<bool> present(const graph::Graph& own) = 0;
};

/// Where simulated devices read the simulated patient's truth from; empty: the agent's own
/// replica (`own` in the calls above, which real devices ignore).
using TruthSource = std::function<const graph::Graph*()>;

/// Simulated sensors reading `sim_patient`'s attributes in `truth` (present; said_seq, said_text,
/// said_for; tap_seq, tap_option, tap_for). When `truth` gives null or no such node: no reading.
std::unique_ptr<SpeechInput> simulated_speech_input(TruthSource truth);
std::unique_ptr<TouchInput> simulated_touch_input(TruthSource truth);
std::unique_ptr<PersonSensor> simulated_person_sensor(TruthSource truth);

}  // namespace quiver::agents::inline apps::barthel
