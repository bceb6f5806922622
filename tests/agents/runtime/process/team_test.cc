// Team files (docs/teams.md): what parses, what each bad field is told, and the team domain's
// DDS configuration.
#include "quiver/agents/runtime/process/team.h"

#include <gtest/gtest.h>

namespace quiver::agents {
namespace {

const char* kGood = R"({"team": "crew", "domain": 9, "lease_s": 2,
  "robots": [{"name": "A", "address": "10.77.0.1"}, {"name": "B-2", "address": "10.77.0.2"}]})";

TEST(TeamFileTest, AGoodFileParses) {
  auto t = parse_team_file(kGood, "team.json");
  ASSERT_TRUE(t.ok()) << t.error().to_string();
  EXPECT_EQ(t->team, "crew");
  EXPECT_EQ(t->domain, 9u);
  EXPECT_EQ(t->lease_s, 2);
  ASSERT_EQ(t->robots.size(), 2u);
  EXPECT_EQ(t->robot("B-2")->address, "10.77.0.2");
  EXPECT_EQ(t->robot("C"), nullptr);
}

TEST(TeamFileTest, EachBadFieldIsNamed) {
  const std::pair<const char*, const char*> cases[] = {
      {"[1, 2]", "not a JSON object"},
      {"{\"team\": \"crew\"", "not a JSON object"},
      {R"({"robots": [{"name": "A", "address": "10.0.0.1"}]})", "\"team\""},
      {R"({"team": "a b", "robots": [{"name": "A", "address": "10.0.0.1"}]})", "\"team\""},
      {R"({"team": "t", "domain": 231, "robots": [{"name": "A", "address": "10.0.0.1"}]})", "\"domain\""},
      {R"({"team": "t", "domain": -1, "robots": [{"name": "A", "address": "10.0.0.1"}]})", "\"domain\""},
      {R"({"team": "t", "lease_s": 0, "robots": [{"name": "A", "address": "10.0.0.1"}]})", "\"lease_s\""},
      {R"({"team": "t", "robots": []})", "\"robots\""},
      {R"({"team": "t", "robots": [{"name": "A<", "address": "10.0.0.1"}]})", "robots[0].name"},
      {R"({"team": "t", "robots": [{"name": "A", "address": "127.0.0.1"}]})", "robots[0].address"},
      {R"({"team": "t", "robots": [{"name": "A", "address": "224.0.0.1"}]})", "robots[0].address"},
      {R"({"team": "t", "robots": [{"name": "A", "address": "0.0.0.0"}]})", "robots[0].address"},
      {R"({"team": "t", "robots": [{"name": "A", "address": "10.0.0.1\"/><x"}]})", "robots[0].address"},
      {R"({"team": "t", "robots": [{"name": "A", "address": "10.0.0.1"}, {"name": "A", "address": "10.0.0.2"}]})",
       "robots[1]: robot name 'A' given twice"},
      {R"({"team": "t", "robots": [{"name": "A", "address": "10.0.0.1"}, {"name": "B", "address": "10.0.0.1"}]})",
       "robots[1]: address 10.0.0.1 given twice"},
  };
  for (const auto& [text, what] : cases) {
    auto t = parse_team_file(text, "team.json");
    ASSERT_FALSE(t.ok()) << text;
    EXPECT_EQ(t.error().code, ErrorCode::kMalformed) << text;
    EXPECT_NE(t.error().message.find("team.json: "), std::string::npos) << t.error().message;
    EXPECT_NE(t.error().message.find(what), std::string::npos) << text << " -> " << t.error().message;
  }
  auto missing = load_team_file("/nonexistent/team.json");
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error().code, ErrorCode::kIo);
}

TEST(TeamFileTest, TheTeamDomainBindsTheRobotsAddressAndListsEveryRobot) {
  auto t = parse_team_file(kGood, "team.json");
  ASSERT_TRUE(t.ok());
  DdsConfig base;
  base.name = "A-gateway.team";
  auto c = team_dds_config(*t, "A", base);
  ASSERT_TRUE(c.ok()) << c.error().to_string();
  EXPECT_EQ(c->domain, 9u);
  EXPECT_EQ(c->lease_ns, 2'000'000'000);
  EXPECT_EQ(c->name, "A-gateway.team");
  EXPECT_EQ(c->source, DdsConfig::Source::kXml);
  for (const char* part : {"<NetworkInterface address=\"10.77.0.1\"/>", "<AllowMulticast>false</AllowMulticast>",
                           "<Peer address=\"10.77.0.1\"/><Peer address=\"10.77.0.2\"/>", "<Tag>quiver-team-crew</Tag>",
                           "<LeaseDuration>2000ms</LeaseDuration>", "<DontRoute>true</DontRoute>"})
    EXPECT_NE(c->xml.find(part), std::string::npos) << part << " in " << c->xml;
  auto unknown = team_dds_config(*t, "C", base);
  ASSERT_FALSE(unknown.ok());
  EXPECT_EQ(unknown.error().code, ErrorCode::kNotFound);
}

}  // namespace
}  // namespace quiver::agents
