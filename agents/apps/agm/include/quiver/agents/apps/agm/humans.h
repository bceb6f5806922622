#pragma once
/// @file
/// The human-tracking agent (AGM, seed 001, III-C): `people` people of 15 joints each, tracked at
/// `rate_hz`; each frame is one transaction per person holding the RT poses of its 15 joints
/// (person -> joint), stamped with the agent's clock — with 2 people at 30 Hz, 900 pose updates
/// a second in 60 deltas. The joints follow a simulated body (standing, breathing, arms and head
/// swaying, each person in its own phase). Grammar: grammars/humans.aggl (poses only).
#include <cstdint>

#include "quiver/agents/runtime/api/agent.h"

namespace quiver::agents::inline apps::agm {

struct HumansOptions {
  int people = 2;
  double rate_hz = 30;
};

/// The joints' names, in order: head, neck, torso, shoulders, elbows, hands, hips, knees, feet.
const std::vector<std::string>& joint_names();

class Humans final : public Agent {
 public:
  explicit Humans(HumansOptions o = {}, std::string name = "humans");
  void setup(AgentContext& ctx) override;
  void status(nlohmann::json& out) const override;
  /// Stops tracking (the simulator quiets the scenario at its end); setup() state is kept.
  void stop_tracking() { stopped_ = true; }
  std::uint64_t updates() const { return updates_; }

 private:
  void frame(AgentContext& ctx);
  HumansOptions opt_;
  bool stopped_ = false;
  std::uint64_t frames_ = 0, updates_ = 0, refused_ = 0;
  std::int64_t first_ns_ = -1, last_ns_ = -1;
};

}  // namespace quiver::agents::inline apps::agm
