#pragma once
/// @file
/// The Planner agent (PELEA's role in seed 000): it conducts the Barthel test by writing each step
/// into the graph: what to say and show (`test -[say]-> u`), and the test's progress as
/// attributes of `test`. It watches the others' results (spoken, heard, touched, the person lost)
/// and replans: no answer in time -> the options again, by voice and all of them on the screen;
/// a second silence -> the next item; two unanswered items -> the clinician is paged and the
/// result stored; the person lost -> "please sit down", and the interrupted item resumes when the
/// person is back. It holds the `test` scope (priority 3) while it conducts; everything it knows is
/// in the graph, so a restarted or second Planner continues where the first stopped. Answer
/// deadlines stand still while the person is away or an agent the test needs (speech, panel,
/// person) is not heard. Grammar: grammars/planner.aggl.
#include <cstdint>
#include <memory>
#include <string>

#include "quiver/agents/devices/pager.h"
#include "quiver/agents/devices/result_store.h"
#include "quiver/agents/runtime/api/agent.h"

namespace quiver::agents::inline apps::barthel {

struct PlannerOptions {
  std::int64_t answer_timeout_ns = 8'000'000'000;
  std::int64_t lock_priority = 3;
  /// The agents whose silence suspends the answer deadlines (empty: none).
  std::vector<std::string> needs = {"speech", "panel", "person"};
};

class Planner final : public Agent {
 public:
  /// `store` and `pager` may be owned elsewhere (the simulator keeps them across restarts).
  Planner(devices::ResultStore& store, devices::Pager& pager, PlannerOptions o = {}, std::string name = "planner");
  /// Owns its devices.
  Planner(std::unique_ptr<devices::ResultStore> store, std::unique_ptr<devices::Pager> pager, PlannerOptions o = {},
          std::string name = "planner");
  ~Planner() override;
  void setup(AgentContext& ctx) override;
  void status(nlohmann::json& out) const override;

 private:
  class Conduct;
  std::unique_ptr<devices::ResultStore> owned_store_;
  std::unique_ptr<devices::Pager> owned_pager_;
  devices::ResultStore& store_;
  devices::Pager& pager_;
  PlannerOptions opt_;
  std::uint64_t steps_ = 0;
  std::string state_;
};

/// The result the graph holds for the test (status, the answers so far, the total).
devices::TestResult result_from_graph(const graph::Graph& g, std::int64_t now_ns);

}  // namespace quiver::agents::inline apps::barthel
