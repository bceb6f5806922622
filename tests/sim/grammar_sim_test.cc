// Valid concurrent changes that merge into a forbidden state are flagged alike everywhere, and
// the designated agent repairs them.

#include <gtest/gtest.h>

#include "quiver/agents/rules/grammar/grammar.h"
#include "quiver/sim/simulator.h"
#include "test_seed.h"

namespace quiver::sim {
namespace {

const char* kRooms = R"(grammar rooms
types { robot room }
constraint robotInOneRoom { forbid { r:robot a:room b:room  r->a(in)  r->b(in) } }
)";

TEST(GrammarSimTest, MergedViolationsAreTheSameOnEveryReplica) {
  const auto base = quiver::testing::base_seed("GrammarSimTest.MergedViolationsAreTheSameOnEveryReplica", 8000);
  auto checker = agents::GrammarChecker(*agents::parse_grammar(kRooms, "rooms"));
  int with_violations = 0;
  const int n = quiver::testing::seed_count(60);
  for (int i = 0; i < n; ++i) {
    SimConfig c = mixed_config(base + i, 120);
    c.faults.crashes = false;  // every replica keeps its history, so all hold the same state
    c.rooms.enabled = true;
    c.rooms.repair = false;
    std::vector<std::vector<agents::Violation>> found;
    c.inspect = [&](const std::vector<const graph::Graph*>& gs) {
      for (const graph::Graph* g : gs) found.push_back(checker.all_violations(*g));
    };
    SimResult r = run_simulation(c);
    ASSERT_TRUE(r.ok()) << "replay with QUIVER_SEED=" << c.seed << "\n" << r.to_json();
    for (const auto& f : found) ASSERT_EQ(f, found[0]) << "replay with QUIVER_SEED=" << c.seed;
    with_violations += found[0].empty() ? 0 : 1;
  }
  std::printf("[grammar] %d of %d schedules ended with the robot in several rooms, flagged alike everywhere\n",
              with_violations, n);
  EXPECT_GT(with_violations, 0) << "concurrent moves must produce merged violations in some schedules";
}

TEST(GrammarSimTest, TheDesignatedAgentRepairsViolations) {
  const auto base = quiver::testing::base_seed("GrammarSimTest.TheDesignatedAgentRepairsViolations", 9000);
  std::uint64_t repairs = 0;
  for (int i = 0; i < quiver::testing::seed_count(60); ++i) {
    SimConfig c = mixed_config(base + i, 120);
    c.rooms.enabled = true;
    SimResult r = run_simulation(c);
    ASSERT_TRUE(r.ok()) << "replay with QUIVER_SEED=" << c.seed << "\n" << r.to_json();
    EXPECT_EQ(r.final_violations, 0u) << "replay with QUIVER_SEED=" << c.seed;
    repairs += r.repairs;
  }
  EXPECT_GT(repairs, 0u);
}

}  // namespace
}  // namespace quiver::sim
