#pragma once
/// @file
/// The Person agent (seed 000; the AGM paper's human tracking): reads the person sensor at
/// `rate_hz`, publishes the 15 body joints as RT poses under `body` and the reading's time
/// (`person.seen_ns`) in one change, and writes whether someone sits in front of the robot as the
/// edge `person -[in_front_of]-> robot`. The person lost: the edge goes (with `person.lost_ns`,
/// the time of that commit). It holds the `person` scope at priority 5, above every other agent,
/// for as long as it runs. Grammar: grammars/person.aggl.
#include <cstdint>
#include <memory>

#include "quiver/agents/apps/barthel/inputs.h"
#include "quiver/agents/runtime/api/agent.h"

namespace quiver::agents::inline apps::barthel {

struct PersonOptions {
  double rate_hz = 30;
  bool joints = true;  ///< publish the 15 joints' poses with every reading
  std::int64_t lock_priority = 5;
};

class Person final : public Agent {
 public:
  Person(std::unique_ptr<PersonSensor> sensor, PersonOptions o = {}, std::string name = "person");
  ~Person() override;
  void setup(AgentContext& ctx) override;
  void status(nlohmann::json& out) const override;

 private:
  void read(AgentContext& ctx);
  std::unique_ptr<PersonSensor> sensor_;
  PersonOptions opt_;
  std::uint64_t readings_ = 0, refused_ = 0, lost_ = 0, arrived_ = 0;
};

}  // namespace quiver::agents::inline apps::barthel
