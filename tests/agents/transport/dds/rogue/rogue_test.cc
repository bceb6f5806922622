// The rogue suite: honest `quiver agent` processes write a shared graph while `quiver_rogue`
// publishes hostile samples on every Quiver topic (random bytes, truncated and oversized
// samples, huge counts, counters at 2^64-1, other replicas' sequence ranges and dots, a forgery
// under a victim's name, lying summaries, pull floods, invented senders). Every agent must stay
// up, keep its memory bounded, log one clear line per kind of bad input (rate-limited), and the
// honest agents must converge afterwards. Everything stays on the loopback configuration; ctest
// also runs it in a private network namespace.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>

#include "agent_procs.h"

namespace quiver::tools {
namespace {

class RogueTest : public AgentProcs, public ::testing::Test {};

std::string slurp(const std::string& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

TEST_F(RogueTest, HonestAgentsSurviveAndConvergeUnderAttack) {
  const std::uint32_t domain = 181;
  const double attack_s = 12;
  std::vector<std::unique_ptr<AgentProc>> agents;
  std::vector<std::string> logs;
  for (int i = 0; i < 3; ++i) {
    logs.push_back(::testing::TempDir() + "/quiver_rogue_agent" + std::to_string(i) + ".err");
    agents.push_back(start("honest" + std::to_string(i), domain,
                           {"--churn-hz", "20", "--churn-for", "16", "--seed", std::to_string(500 + i)}, logs.back()));
  }
  ASSERT_TRUE(poll_until(agents, 30'000, 50, [&] {
    for (auto& a : agents)
      if (!a->last.is_object() || a->last["peers"] < 2) return false;
    return true;
  })) << "the honest agents meet";
  long rss_before = 0;
  for (auto& a : agents) rss_before = std::max(rss_before, a->last["rss_kb"].get<long>());

  auto rogue = Subprocess::spawn({QUIVER_ROGUE, "--domain", std::to_string(domain), "--seconds",
                                  std::to_string(attack_s), "--seed", "7"});
  ASSERT_TRUE(rogue.has_value());
  long rss_peak = rss_before;
  std::string report;
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(90);
  while (std::chrono::steady_clock::now() < until) {
    if (auto line = rogue->read_line(200)) report = *line;
    poll(agents);
    for (auto& a : agents)
      if (a->last.is_object()) rss_peak = std::max(rss_peak, a->last["rss_kb"].get<long>());
    if (rogue->wait(0) >= 0) break;
  }
  ASSERT_EQ(rogue->wait(5'000), 0) << "the rogue ran";
  std::printf("[rogue] %s\n", report.c_str());
  json sent = json::parse(report, nullptr, false);
  ASSERT_TRUE(sent.is_object());
  for (const char* kind : {"random_bytes", "truncated", "huge_counts", "bad_counters", "claim_others_numbers",
                           "others_dots", "lying_summary", "pull_flood", "sybils", "forgery"})
    EXPECT_GT(sent["sent"].value(kind, 0), 0) << kind << " was never sent: the suite would check nothing";
  EXPECT_GT(sent["victims"].get<int>(), 0);

  // Every agent is still up; the honest ones converge once their writes stop.
  for (auto& a : agents) EXPECT_EQ(a->proc.wait(0), -1) << a->name << " died";
  const std::string digest = wait_converged(agents, 60'000, 2);
  EXPECT_NE(digest, "") << "the honest agents converge after the attack";
  EXPECT_EQ(dump_digest(domain), digest) << "a fresh observer syncs to the same state";
  std::printf("[rogue] resident memory: %ld KiB before, %ld KiB at most during the attack\n", rss_before, rss_peak);
  EXPECT_LT(rss_peak, rss_before + 400 * 1024) << "memory stays bounded";
  std::uint64_t rejected = 0, equivocations = 0, divergences = 0;
  for (auto& a : agents) {
    rejected += a->last["rejected"].get<std::uint64_t>();
    equivocations += a->last["equivocations"].get<std::uint64_t>();
    divergences += a->last.value("divergences", std::uint64_t{0});
  }
  std::printf("[rogue] %llu packets refused, %llu equivocations reported, %llu divergences found by the digest\n",
              static_cast<unsigned long long>(rejected), static_cast<unsigned long long>(equivocations),
              static_cast<unsigned long long>(divergences));
  EXPECT_GT(rejected, 100u) << "the bad input reached the agents and was refused";
  EXPECT_GT(equivocations, 0u) << "the forgery and the equivocations were seen";

  for (auto& a : agents) {
    a->proc.kill(SIGTERM);
    a->proc.wait(10'000);
  }
  // Logs: each kind of refusal is reported, but rate-limited: one line per kind at first, then
  // one summary line per kind per 5 s.
  for (std::size_t i = 0; i < logs.size(); ++i) {
    const std::string log = slurp(logs[i]);
    std::map<std::string, int> lines;
    std::istringstream in(log);
    std::string line;
    std::regex kind_re("rejected: (?:[0-9]+ more )?([a-z_]+)");
    int total = 0, all_lines = 0;
    while (std::getline(in, line)) {
      ++all_lines;
      std::smatch m;
      if (std::regex_search(line, m, kind_re)) {
        ++lines[m[1]];
        ++total;
      }
    }
    std::string kinds;
    for (const auto& [k, n] : lines) kinds += k + "=" + std::to_string(n) + " ";
    std::printf("[rogue] honest%zu logged %d rejection lines: %s\n", i, total, kinds.c_str());
    EXPECT_GE(lines["malformed"], 1) << log.substr(0, 2000);
    const int windows = static_cast<int>(attack_s / 5) + 4;
    for (const auto& [k, n] : lines) EXPECT_LE(n, windows) << "kind " << k << " is not rate-limited";
    EXPECT_LT(all_lines, 150) << "the whole log stays readable (invented peers joining included)";
    std::remove(logs[i].c_str());
  }
}


// The rogue suite with DDS Security and graph-level permissions on (docs/security.md). An
// outsider without credentials reaches nobody: it never hears an agent and nothing it sends is
// even refused. A member with valid credentials reaches the agents: its malformed samples are
// refused as without security, and the deltas it forges under the honest agents' names are
// refused for their signatures. The honest agents converge either way.
TEST_F(RogueTest, WithSecurityAnOutsiderReachesNobodyAndAMemberCannotForge) {
  const std::uint32_t domain = 183;
  char tmpl[] = "/tmp/quiver-rogue-keys-XXXXXX";
  ASSERT_NE(mkdtemp(tmpl), nullptr);
  const std::string keys = tmpl;
  auto run = [](std::vector<std::string> argv) {
    auto p = Subprocess::spawn(argv);
    return p.has_value() && p->wait(30'000) == 0;
  };
  ASSERT_TRUE(run({QUIVER_BIN, "keys", "init", keys}));
  for (const char* n : {"honest0", "honest1", "honest2", "rogue"})
    ASSERT_TRUE(run({QUIVER_BIN, "keys", "add-agent", n, "--dir", keys}));
  std::vector<std::unique_ptr<AgentProc>> agents;
  for (int i = 0; i < 3; ++i)
    agents.push_back(start("honest" + std::to_string(i), domain,
                           {"--security", keys, "--churn-hz", "20", "--churn-for", "30", "--seed", std::to_string(700 + i)}));
  ASSERT_TRUE(poll_until(agents, 30'000, 50, [&] {
    for (auto& a : agents)
      if (!a->last.is_object() || a->last["peers"] < 2) return false;
    return true;
  })) << "the secured agents meet";
  auto totals = [&](const char* key) {
    std::uint64_t n = 0;
    for (auto& a : agents) n += a->last.value(key, std::uint64_t{0});
    return n;
  };
  auto attack = [&](std::vector<std::string> extra) {
    std::vector<std::string> argv = {QUIVER_ROGUE, "--domain", std::to_string(domain), "--seconds", "6", "--seed", "9"};
    argv.insert(argv.end(), extra.begin(), extra.end());
    auto rogue = Subprocess::spawn(argv);
    EXPECT_TRUE(rogue.has_value());
    std::string report;
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (rogue && std::chrono::steady_clock::now() < until) {
      if (auto line = rogue->read_line(200)) report = *line;
      poll(agents);
      if (rogue->wait(0) >= 0) break;
    }
    const int status = rogue ? rogue->wait(5'000) : -2;
    EXPECT_EQ(status, 0) << "the rogue ran (its exit status; above 128 is a signal)";
    std::printf("[rogue, secured agents] %s\n", report.c_str());
    json j = json::parse(report, nullptr, false);
    return j.is_object() ? j : json::object();
  };

  const std::uint64_t rejected0 = totals("rejected");
  json outsider = attack({});
  ASSERT_TRUE(outsider.contains("sent"));
  EXPECT_GT(outsider["sent"].value("random_bytes", 0), 0) << "the outsider did attack";
  EXPECT_EQ(outsider["victims"].get<int>(), 0) << "it never heard an agent";
  poll(agents);
  EXPECT_EQ(totals("rejected"), rejected0) << "nothing it sent reached an agent";

  json member = attack({"--security", keys, "--name", "rogue"});
  ASSERT_TRUE(member.contains("sent"));
  EXPECT_GT(member["victims"].get<int>(), 0) << "a member hears the agents";
  EXPECT_GT(member["sent"].value("forgery", 0), 0);
  poll(agents);
  EXPECT_GT(totals("rejected"), rejected0 + 10) << "its bad samples reached the agents and were refused";
  EXPECT_GT(totals("refused"), 0u) << "its forgeries failed their signature checks";

  for (auto& a : agents) EXPECT_EQ(a->proc.wait(0), -1) << a->name << " died";
  const std::string digest = wait_converged(agents, 60'000, 2);
  EXPECT_NE(digest, "") << "the honest agents converge after both attacks";
  std::printf("[rogue, secured agents] %llu packets refused, %llu deltas or states refused by the permissions\n",
              static_cast<unsigned long long>(totals("rejected")), static_cast<unsigned long long>(totals("refused")));
  for (auto& a : agents) {
    a->proc.kill(SIGTERM);
    a->proc.wait(10'000);
  }
  std::filesystem::remove_all(keys);
}

}  // namespace
}  // namespace quiver::tools
