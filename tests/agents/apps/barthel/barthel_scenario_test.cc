// The Barthel test in the simulator: each path of the test (happy, timeouts, two unanswered items,
// the person lost mid-sentence, the Planner killed), and the scenario file's errors.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "quiver/agents/apps/barthel/sim/barthel_scenario.h"

namespace quiver::sim {
namespace {

using agents::barthel::PatientScript;
using agents::barthel::ReplyKind;
using agents::barthel::run_scenario;
using Scenario = agents::barthel::BarthelScenario;
using ScenarioResult = agents::barthel::BarthelResult;
using nlohmann::json;

Scenario base(std::uint64_t patient_seed) {
  Scenario s;
  s.script = PatientScript::random(patient_seed);
  s.timing.words_ms = 60;
  s.timing.answer_timeout_s = 3;
  return s;
}

ScenarioResult run(const Scenario& s, std::uint64_t seed = 1) {
  ScenarioResult r = run_scenario(s, seed);
  std::printf("seed %llu: %s\n", static_cast<unsigned long long>(seed), r.to_json().dump().c_str());
  return r;
}

TEST(BarthelScenario, HappyPathStoresTheScoreTheAnswersImply) {
  Scenario s = base(3);
  s.checks.status = "completed";
  ScenarioResult r = run(s);
  EXPECT_TRUE(r.passed) << r.to_json().dump();
  EXPECT_EQ(r.status, "completed");
  EXPECT_EQ(r.total, s.script.expected().total);
  EXPECT_EQ(r.interruptions, 0);
}

TEST(BarthelScenario, SilenceRepeatsTheOptionsThenTheNextItem) {
  Scenario s = base(4);
  s.script.items[0].first = {ReplyKind::kSilent, 0};
  s.script.items[0].second = {ReplyKind::kTouch, 2};   // answered on the screen the second time
  s.script.items[5].first = {ReplyKind::kMisunderstand, 0};
  s.script.items[5].second = {ReplyKind::kVoice, 1};
  s.script.items[7].first = {ReplyKind::kSilent, 0};
  s.script.items[7].second = {ReplyKind::kSilent, 0};  // one unanswered item: the test goes on
  ScenarioResult r = run(s);
  EXPECT_TRUE(r.passed) << r.to_json().dump();
  EXPECT_EQ(r.status, "completed");
  EXPECT_EQ(r.total, s.script.expected().total);
}

TEST(BarthelScenario, TwoUnansweredItemsCallTheClinician) {
  Scenario s = base(5);
  for (int i : {2, 6}) s.script.items[static_cast<std::size_t>(i)] = {{ReplyKind::kSilent, 0}, {ReplyKind::kMisunderstand, 0}};
  s.checks.status = "clinician_called";
  ScenarioResult r = run(s);
  EXPECT_TRUE(r.passed) << r.to_json().dump();
  EXPECT_EQ(r.status, "clinician_called");
  EXPECT_EQ(r.total, s.script.expected().total);
}

TEST(BarthelScenario, PersonLostMidSentenceStopsSpeechAndTheItemResumes) {
  Scenario s = base(6);
  s.script.leaves = {{3, 700'000'000, 4'000'000'000}, {8, 300'000'000, 2'000'000'000}};
  s.checks.never_speaking_absent_ms = 300;
  ScenarioResult r = run(s);
  EXPECT_TRUE(r.passed) << r.to_json().dump();
  EXPECT_GE(r.interruptions, 2) << "the question was not interrupted: the check ran on nothing";
  EXPECT_LE(r.max_speaking_absent_ms, 300.0);
  EXPECT_EQ(r.total, s.script.expected().total);
}

TEST(BarthelScenario, PlannerKilledMidItemContinuesFromTheGraph) {
  for (double at : {6.0, 17.0, 29.0}) {
    Scenario s = base(7);
    s.faults = {{FaultEvent::Kind::kKill, at, {}, "planner", 0}, {FaultEvent::Kind::kRestart, at + 0.5, {}, "planner", 0}};
    ScenarioResult r = run(s);
    EXPECT_TRUE(r.passed) << "kill at " << at << ": " << r.to_json().dump();
    EXPECT_EQ(r.kills, 1);
  }
}

TEST(BarthelScenario, AFixedSeedReplaysExactly) {
  Scenario s = Scenario::random_faults(42);
  ScenarioResult a = run_scenario(s, 42), b = run_scenario(s, 42);
  EXPECT_EQ(a.to_json(), b.to_json());
}

TEST(BarthelScenario, FileErrorsNameTheValue) {
  auto bad = [](const char* text) {
    auto r = Scenario::parse(json::parse(text), "s.json");
    EXPECT_FALSE(r.ok()) << text;
    return r.ok() ? std::string() : r.error().message;
  };
  EXPECT_NE(bad(R"({"faults": [{"at_s": 1, "kill": "executive"}]})").find("s.json:/faults/0/kill"), std::string::npos);
  EXPECT_NE(bad(R"({"faults": [{"at_s": -1, "heal": true}]})").find("/faults/0"), std::string::npos);
  EXPECT_NE(bad(R"({"checks": {"total": "high"}})").find("/checks/total"), std::string::npos);
  EXPECT_NE(bad(R"({"patient": {"script": {"items": []}}})").find("/patient/script"), std::string::npos);
  EXPECT_NE(bad(R"({"limit": 3})").find("/limit: unknown key"), std::string::npos);
  auto ok = Scenario::parse(json::parse(R"({"patient": {"seed": 2, "varied": true},
      "faults": [{"at_s": 1, "partition": [["planner"], ["speech"]]}, {"at_s": 2, "heal": true}]})"), "s.json");
  ASSERT_TRUE(ok.ok()) << ok.error().message;
  EXPECT_EQ(ok->faults.size(), 2u);
}

}  // namespace
}  // namespace quiver::sim
