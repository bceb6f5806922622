#pragma once
// The 'person' of clean-table: someone in the house who, at a given time, puts the first mug back
// on the table (if the robot does not carry it), under its own grammar (rule putBack). The world
// then deviates from the plan and the planner agent must plan again.
#include <cstdint>

#include "quiver/agents/runtime/api/agent.h"

namespace quiver::agents::inline apps::agm::internal {

class PutBack final : public Agent {
 public:
  explicit PutBack(std::int64_t at_ns);
  void setup(AgentContext& ctx) override;

 private:
  std::int64_t at_ns_;
  bool done_ = false;
};

}  // namespace quiver::agents::inline apps::agm::internal
