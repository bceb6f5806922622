// Graph-level permissions (docs/security.md): the policy file, the check on local commit, and
// the check every receiver makes on deltas and states, so that a change its author may not make
// is applied nowhere and the replicas stay equal.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstring>

#include "quiver/agents/rules/permissions/actions.h"
#include "quiver/agents/rules/permissions/policy_admission.h"
#include "quiver/agents/replica/replication/replicator.h"
#include "quiver/graph/codec.h"
#include "quiver/base/hash.h"
#include "test_net.h"

namespace quiver::agents {
namespace {

using graph::Graph;
using graph::NodeId;
using graph::Symbol;
using graph::Value;
using permissions::Policy;
using permissions::PolicyAdmission;

constexpr const char* kPolicy = R"({
  "default": "allow",
  "rules": [
    {"action": "write",  "target": "speaking",     "agents": ["speech"]},
    {"action": "rt",     "target": "person_joint", "agents": ["person"]},
    {"action": "create", "target": "person",       "agents": ["person"]},
    {"action": "delete", "target": "person",       "agents": ["person"]},
    {"action": "edge",   "target": "talking_to",   "agents": ["speech"]},
    {"action": "lock",   "target": "robot",        "agents": ["navigation"]}
  ]})";

Policy policy() {
  auto p = Policy::parse(kPolicy, "test policy");
  EXPECT_TRUE(p.ok()) << p.error().to_string();
  p->learn_name("panel");
  p->learn_name("intruder");
  return *p;
}

TEST(PolicyTest, RulesDecideFirstMatchAndTheDefaultTheRest) {
  Policy p = policy();
  const std::uint64_t speech = fnv1a64("speech"), panel = fnv1a64("panel");
  const Symbol robot("robot"), speaking("speaking"), battery("battery");
  EXPECT_TRUE(p.check(speech, permissions::Action::kWrite, robot, speaking).ok());
  Status s = p.check(panel, permissions::Action::kWrite, robot, speaking);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().code, ErrorCode::kPermissionDenied);
  EXPECT_NE(s.error().message.find("agent '" + std::string("panel") + "'"), std::string::npos) << s.error().message;
  EXPECT_NE(s.error().message.find("rule 1"), std::string::npos) << s.error().message;
  EXPECT_TRUE(p.check(panel, permissions::Action::kWrite, robot, battery).ok()) << "no rule: the default allows";
  auto deny = Policy::parse(R"({"default": "deny", "rules": [{"action": "write", "target": "robot.*", "agents": ["*"]}]})", "p");
  ASSERT_TRUE(deny.ok());
  EXPECT_TRUE(deny->check(panel, permissions::Action::kWrite, robot, battery).ok());
  EXPECT_FALSE(deny->check(panel, permissions::Action::kWrite, Symbol("mug"), battery).ok());
  EXPECT_FALSE(deny->check(panel, permissions::Action::kCreate, robot, Symbol()).ok());
}

TEST(PolicyTest, ABadPolicyFileSaysWhichRuleAndWhat) {
  struct Case {
    const char* text;
    const char* says;
  } cases[] = {
      {"[1]", "a policy is a JSON object"},
      {R"({"rules": [{"action": "fly", "target": "x", "agents": []}]})", "rule 1: unknown action \"fly\""},
      {R"({"rules": [{"action": "write", "target": "x", "agents": ["a"]}, {"action": "edge", "target": "a.b", "agents": []}]})",
       "rule 2: a edge rule's target is a type"},
      {R"({"rules": [{"action": "write", "target": ".x", "agents": []}]})", "rule 1: the target \".x\""},
      {R"({"default": "maybe"})", "\"default\" must be"},
      {R"({"rules": [{"action": "write", "target": "x"}]})", "rule 1: \"agents\""},
      {R"({"rulez": []})", "unknown key \"rulez\""},
      {"{", "JSON syntax error"},
      {R"({"rules": [], "x": 5e555})", "number overflow"},  // nlohmann throws out_of_range, not parse_error
  };
  for (const Case& c : cases) {
    auto p = Policy::parse(c.text, "policy.json");
    ASSERT_FALSE(p.ok()) << c.text;
    EXPECT_NE(p.error().message.find("policy.json: "), std::string::npos) << p.error().message;
    EXPECT_NE(p.error().message.find(c.says), std::string::npos) << c.text << " -> " << p.error().message;
  }
}

// The commit check refuses what the agent may not do, and the graph stays as it was.
TEST(PermissionsTest, ALocalCommitOutsideThePolicyIsRefusedAndChangesNothing) {
  auto adm = std::make_unique<PolicyAdmission>(policy(), nullptr, nullptr);
  Graph g(graph::ReplicaId{fnv1a64("panel"), 1});
  g.set_permission_check(adm->commit_check(fnv1a64("panel")));
  auto tx = g.begin();
  auto robot = tx.create_node("robot", "robot");
  ASSERT_TRUE(robot.ok());
  ASSERT_TRUE(tx.set(*robot, "battery", Value(0.5)).ok());
  ASSERT_TRUE(tx.commit().ok()) << "allowed by the default";
  const auto before = g.digest();
  auto tx2 = g.begin();
  ASSERT_TRUE(tx2.set(*robot, "speaking", Value(true)).ok());
  auto c = tx2.commit();
  ASSERT_FALSE(c.ok());
  EXPECT_EQ(c.error().code, ErrorCode::kPermissionDenied);
  EXPECT_NE(c.error().message.find("may not write 'speaking' on 'robot'"), std::string::npos) << c.error().message;
  EXPECT_EQ(g.digest(), before);
  // Creating a node with a reserved attribute is writing it; a person is the person agent's.
  auto tx3 = g.begin();
  ASSERT_TRUE(tx3.create_node("robot", "r2", {{"speaking", Value(false)}}).ok());
  EXPECT_FALSE(tx3.commit().ok());
  auto tx4 = g.begin();
  ASSERT_TRUE(tx4.create_node("person", "p").ok());
  EXPECT_FALSE(tx4.commit().ok());
  EXPECT_EQ(g.digest(), before);
}

// Three replicas: speech, panel (both honest, checking on commit and on merge) and a rogue panel
// whose own commit check is off (a modified agent). What the rogue may not do is refused by
// both honest replicas, which end equal, and what it may do reaches them.
struct Trio {
  Net net;
  int speech, panel, rogue;
  std::vector<std::unique_ptr<PolicyAdmission>> adm;
  Trio() {
    speech = net.add(fnv1a64("speech"));
    panel = net.add(fnv1a64("panel"));
    rogue = net.add(fnv1a64("intruder"));
    for (int i : {speech, panel, rogue}) {
      adm.push_back(std::make_unique<PolicyAdmission>(policy(), nullptr, nullptr));
      net.nodes[i].rep->set_admission(adm.back().get());
      if (i != rogue)
        net.nodes[i].g->set_permission_check(adm.back()->commit_check(net.nodes[i].g->replica().agent));
    }
    net.pump();
  }
  Graph& g(int i) { return *net.nodes[i].g; }
  const ReplicatorStats& stats(int i) { return net.nodes[i].rep->stats(); }
};

TEST(PermissionsTest, EveryReplicaRefusesADeltaItsOriginMayNotMakeAndTheyStayEqual) {
  Trio t;
  NodeId robot;
  {
    auto tx = t.g(t.speech).begin();
    robot = *tx.create_node("robot", "robot");
    ASSERT_TRUE(tx.set(robot, "speaking", Value(false)).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  t.net.advance(200'000'000);
  ASSERT_TRUE(t.g(t.rogue).has_node(robot));
  // The control: the same kind of write by an agent the policy lets do it reaches everyone.
  {
    auto tx = t.g(t.rogue).begin();
    ASSERT_TRUE(tx.set(robot, "battery", Value(0.9)).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  t.net.advance(200'000'000);
  ASSERT_TRUE(t.g(t.panel).get<double>(robot, "battery").ok());
  EXPECT_EQ(t.stats(t.panel).deltas_refused, 0u);
  // The rogue writes what only speech may write.
  {
    auto tx = t.g(t.rogue).begin();
    ASSERT_TRUE(tx.set(robot, "speaking", Value(true)).ok());
    ASSERT_TRUE(tx.commit().ok()) << "its own check is off";
  }
  // Long enough for gossip too, which sends the state digest to one peer per second, in turn (a
  // replica pulls a whole state after two differing digests in a row from one peer: about 4 s
  // with two peers).
  t.net.advance(5'000'000'000);
  for (int i : {t.speech, t.panel}) {
    EXPECT_EQ(*t.g(i).get<bool>(robot, "speaking"), false) << "refused at replica " << i;
    EXPECT_GE(t.stats(i).deltas_refused, 1u);
    bool reported = false;
    for (const Error& e : t.net.nodes[i].errors)
      reported = reported || (e.code == ErrorCode::kPermissionDenied &&
                              e.message.find("may not write 'speaking' on 'robot'") != std::string::npos);
    EXPECT_TRUE(reported) << "replica " << i << " reports the refusal";
  }
  EXPECT_EQ(t.g(t.speech).digest(), t.g(t.panel).digest());
  EXPECT_EQ(t.stats(t.speech).states_applied + t.stats(t.panel).states_applied, 0u)
      << "the honest replicas agree without pulling states";
  // The rogue's state holds the forbidden value: a state transfer from it is refused too.
  EXPECT_GE(t.stats(t.speech).states_refused + t.stats(t.panel).states_refused, 1u)
      << "the digest check pulled the rogue's whole state, and refused it";
  // Later writes still flow.
  {
    auto tx = t.g(t.speech).begin();
    ASSERT_TRUE(tx.set(robot, "speaking", Value(true)).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  t.net.advance(500'000'000);
  EXPECT_EQ(*t.g(t.panel).get<bool>(robot, "speaking"), true);
  EXPECT_EQ(t.g(t.speech).digest(), t.g(t.panel).digest());
}

// The fast path (docs/security.md): a delta that arrives straight from its origin's own
// (authenticated) sender is admitted without verifying its signature, one relayed by another is
// verified. A member that signs its own deltas badly on purpose is then admitted where it sent them
// and refused where they were relayed; the (origin, seq) sets are equal, the digests differ, and
// the digest repair brings the state over (the policy lets that member write it): they converge.
TEST(PermissionsTest, ABadlySignedDeltaStraightFromItsOriginIsAdmittedThereAndTheDigestRepairEvensTheRest) {
  Net net;
  const int speech = net.add(fnv1a64("speech")), panel = net.add(fnv1a64("panel")),
            other = net.add(fnv1a64("intruder"));
  // Stand-ins for the keys: a signature is the agent's id and the payload's length; speech's
  // signer is broken. A sender key is the sending node's agent id.
  auto key_of = [&](int i) {
    std::array<std::uint8_t, 16> k{};
    const std::uint64_t agent = net.nodes[i].g->replica().agent;
    std::memcpy(k.data(), &agent, sizeof agent);
    return k;
  };
  net.sender = key_of;
  auto signature = [](std::uint64_t agent, std::size_t n) {
    std::vector<std::uint8_t> s(16);
    std::memcpy(s.data(), &agent, 8);
    std::memcpy(s.data() + 8, &n, 8);
    return s;
  };
  std::vector<std::unique_ptr<PolicyAdmission>> adm;
  for (int i : {speech, panel, other}) {
    const std::uint64_t self = net.nodes[i].g->replica().agent;
    auto sign = [=](std::span<const std::uint8_t> p) {
      return i == speech ? std::vector<std::uint8_t>{0xde, 0xad} : signature(self, p.size());
    };
    auto verify = [=](std::uint64_t agent, std::span<const std::uint8_t> data, std::span<const std::uint8_t> sig) {
      const auto want = signature(agent, data.size());
      return std::equal(sig.begin(), sig.end(), want.begin(), want.end()) ? Status{}
                                                                          : make_error(ErrorCode::kRefused, "bad signature");
    };
    auto sent_by = [](std::uint64_t agent, std::span<const std::uint8_t> sender) {
      std::uint64_t who = 0;
      std::memcpy(&who, sender.data(), 8);
      return sender.size() == 16 && who == agent;
    };
    adm.push_back(std::make_unique<PolicyAdmission>(policy(), sign, verify, sent_by));
    net.nodes[i].rep->set_admission(adm.back().get());
  }
  // Speech's own sends to `other` are lost: other gets speech's delta only from panel.
  net.drop = [&](const Packet& p) { return p.from == speech && p.to == other && p.sample.topic == DdsTopic::kDelta; };
  net.pump();
  auto tx = net.nodes[speech].g->begin();
  const NodeId thing = *tx.create_node("thing", "badly_signed");
  ASSERT_TRUE(tx.commit().ok());
  net.advance(300'000'000);
  EXPECT_TRUE(net.nodes[panel].g->has_node(thing)) << "admitted on its sender, straight from speech";
  EXPECT_GE(adm[1]->admitted_on_sender(), 1u);
  EXPECT_FALSE(net.nodes[other].g->has_node(thing)) << "relayed: verified, and refused";
  EXPECT_GE(net.nodes[other].rep->stats().deltas_refused, 1u);
  EXPECT_GE(adm[2]->signatures_verified(), 1u);
  // The digest repair (a digest to one peer per second, in turn; a whole state after two
  // differing in a row) brings it over as state, which the policy lets speech have written.
  net.advance(8'000'000'000);
  EXPECT_TRUE(net.nodes[other].g->has_node(thing));
  EXPECT_GE(net.nodes[other].rep->stats().states_applied, 1u);
  EXPECT_EQ(net.nodes[speech].g->digest(), net.nodes[other].g->digest());
  EXPECT_EQ(net.nodes[panel].g->digest(), net.nodes[other].g->digest());
}

TEST(PermissionsTest, ANewcomerRefusesAStateWithAnEntryItsWriterMayNotHaveWritten) {
  Net net;
  ReplicatorOptions o;
  int rogue = net.add(fnv1a64("intruder"), o);
  NodeId robot;
  {
    auto tx = net.nodes[rogue].g->begin();
    robot = *tx.create_node("robot", "robot");
    ASSERT_TRUE(tx.set(robot, "speaking", Value(true)).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  // Its deltas are gone from its relay buffer: a newcomer must take a state.
  PolicyAdmission adm(policy(), nullptr, nullptr);
  int fresh = net.add(fnv1a64("panel"));
  net.nodes[fresh].rep->set_admission(&adm);
  net.advance(3'000'000'000);
  const auto& st = net.nodes[fresh].rep->stats();
  EXPECT_EQ(net.nodes[fresh].g->node_count(), 0u);
  EXPECT_EQ(st.deltas_applied, 0u);
  EXPECT_GE(st.deltas_refused + st.states_refused, 1u);
  // Control: the same history without the forbidden write is admitted.
  Net net2;
  int writer = net2.add(fnv1a64("intruder"));
  {
    auto tx = net2.nodes[writer].g->begin();
    auto r = *tx.create_node("robot", "robot");
    ASSERT_TRUE(tx.set(r, "battery", Value(1.0)).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  PolicyAdmission adm2(policy(), nullptr, nullptr);
  int fresh2 = net2.add(fnv1a64("panel"));
  net2.nodes[fresh2].rep->set_admission(&adm2);
  net2.advance(3'000'000'000);
  EXPECT_EQ(net2.nodes[fresh2].g->node_count(), 1u);
}

TEST(PermissionsTest, StatesAreCheckedEntryByEntryAgainstEachWriter) {
  Graph g(graph::ReplicaId{fnv1a64("speech"), 1});
  auto tx = g.begin();
  auto robot = *tx.create_node("robot", "robot");
  ASSERT_TRUE(tx.set(robot, "speaking", Value(true)).ok());
  ASSERT_TRUE(tx.commit().ok());
  Policy p = policy();
  EXPECT_TRUE(permissions::check_state(p, g.state()).ok()) << "speech wrote it";
  Graph other(graph::ReplicaId{fnv1a64("panel"), 1});
  other.merge(g.state());
  auto tx2 = other.begin();
  ASSERT_TRUE(tx2.set(robot, "speaking", Value(false)).ok());
  ASSERT_TRUE(tx2.commit().ok());
  Status s = permissions::check_state(p, other.state());
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().message.find("agent 'panel' may not write 'speaking'"), std::string::npos) << s.error().message;
}

// Every op of a delta states its node's type, so receivers decide from the delta alone.
TEST(PermissionsTest, DeltasStateTheTypeOfEveryNodeTheyTouch) {
  Graph g(graph::ReplicaId{7, 1});
  std::vector<graph::GraphDelta> out;
  g.set_delta_sink([&](const graph::GraphDelta& d) { out.push_back(d); });
  auto tx = g.begin();
  auto robot = *tx.create_node("robot", "robot");
  ASSERT_TRUE(tx.commit().ok());
  auto tx2 = g.begin();
  ASSERT_TRUE(tx2.set(robot, "speaking", Value(true)).ok());
  ASSERT_TRUE(tx2.commit().ok());
  ASSERT_EQ(out.size(), 2u);
  std::vector<std::uint8_t> bytes;
  graph::encode(out[1], bytes, 2, 2);
  graph::GraphDelta back;
  ASSERT_TRUE(graph::decode(bytes, back).ok());
  ASSERT_EQ(back.nodes.size(), 1u);
  EXPECT_FALSE(back.nodes[0].has_header);
  EXPECT_EQ(back.nodes[0].type, Symbol("robot"));
  std::vector<std::uint8_t> again;
  graph::encode(back, again, 2, 2);
  EXPECT_EQ(again, bytes) << "a decoded delta re-encodes to the same bytes";
}

}  // namespace
}  // namespace quiver::agents
