#pragma once
/// @file
/// The simulated patient, as an agent of its own: it hears what the robot has said to the end
/// (`speaker -[spoke]-> u`), thinks (a seeded delay), and answers the way its script says (by
/// voice, by touching the option, silence, or something the robot will not understand); it
/// leaves its chair mid-sentence when its script says so, and comes back. It writes only the
/// `sim_patient` node: the ground truth that the simulated microphone, touchscreen and person
/// sensor read (inputs.h). It is the world, not part of the robot: a real deployment has a real
/// person instead. Grammar: grammars/patient.aggl (attributes only).
#include <cstdint>
#include <set>

#include "quiver/agents/apps/barthel/patient_script.h"
#include "quiver/agents/runtime/api/agent.h"

namespace quiver::agents::inline apps::barthel {

class Patient final : public Agent {
 public:
  explicit Patient(PatientScript script, std::string name = "patient");
  void setup(AgentContext& ctx) override;
  void on_tick(AgentContext& ctx) override;
  void status(nlohmann::json& out) const override;
  const PatientScript& script() const { return script_; }

 private:
  Status write(AgentContext& ctx, std::vector<std::pair<std::string, graph::Value>> attrs);
  PatientScript script_;
  std::size_t next_leave_ = 0;
  std::int64_t leave_at_ = -1, back_at_ = -1;
  std::int64_t answered_seq_ = 0;   // the last prompt it has answered (or decided not to)
  std::int64_t pending_seq_ = -1, answer_at_ = -1;
  std::uint64_t answers_ = 0, leaves_ = 0;
};

}  // namespace quiver::agents::inline apps::barthel
