#include "quiver/agents/rules/locks/locks.h"

#include <gtest/gtest.h>

#include "test_net.h"

namespace quiver::agents {
namespace {

using graph::NodeId;
using graph::Symbol;
using graph::Value;

// Replicas on the hand-driven network, each with a lock manager on the network's clock.
struct LockNet {
  Net net;
  std::vector<std::unique_ptr<LockManager>> locks;
  std::vector<std::vector<LockEvent>> events;
  NodeId arm, gripper, person;

  explicit LockNet(int n, std::int64_t lease_ns = 500'000'000) {
    ReplicatorOptions ro;
    ro.heartbeat_ns = 20'000'000;
    ro.lease_ns = 200'000'000;
    // Under gossip a silent peer is noticed by probes: scaled like the lease, a crash is declared
    // within about 0.4 s, as the lease notices it with all-to-all summaries.
    ro.probe_ns = 100'000'000;
    for (int i = 0; i < n; ++i) net.add(100 + i, ro);
    events.resize(n);
    for (int i = 0; i < n; ++i) {
      LockOptions lo;
      lo.lease_ns = lease_ns;
      locks.push_back(std::make_unique<LockManager>(*net.nodes[i].g, net.nodes[i].rep.get(), [this] { return net.now; }, lo));
      locks.back()->install();
      locks.back()->on_event([this, i](const LockEvent& e) { events[i].push_back(e); });
    }
    auto tx = net.nodes[0].g->begin();
    arm = *tx.create_node("arm", "arm");
    gripper = *tx.create_node("gripper", "gripper");
    person = *tx.create_node("person", "person");
    EXPECT_TRUE(tx.set_rt(arm, gripper, graph::Pose{}, 0).ok());
    EXPECT_TRUE(tx.commit().ok());
    advance(100'000'000);
  }
  void advance(std::int64_t ns) {
    for (int k = 0; k < 10; ++k) {
      net.advance(ns / 10, 1);
      for (std::size_t i = 0; i < locks.size(); ++i)
        if (net.nodes[i].rep) locks[i]->tick();
      net.pump();
    }
  }
  bool has(int i, LockEventKind k) const {
    for (const auto& e : events[i])
      if (e.kind == k) return true;
    return false;
  }
  Status write(int i, NodeId n, const char* attr, Value v) {
    auto tx = net.nodes[i].g->begin();
    Status s = tx.set(n, attr, std::move(v));
    if (!s.ok()) return s;
    auto r = tx.commit();
    return r.ok() ? Status{} : Status(r.error());
  }
};

TEST(LocksTest, AcquiredOnceAcknowledgedAndOthersAreRefused) {
  LockNet w(3);
  ASSERT_TRUE(w.locks[0]->acquire(w.arm, 1).ok());
  EXPECT_TRUE(w.locks[0]->pending(w.arm)) << "not held before everyone acknowledged it";
  EXPECT_FALSE(w.locks[0]->holds(w.arm));
  w.advance(200'000'000);
  EXPECT_TRUE(w.locks[0]->holds(w.arm));
  EXPECT_TRUE(w.has(0, LockEventKind::kAcquired));
  // The scope covers the RT subtree: the gripper is locked too. The refusal names the holder as
  // the graph's namer does (a replicator's names the agents by what they announced).
  w.net.nodes[1].g->set_origin_namer([](const graph::ReplicaId& r, std::string& name) { name = "agent" + std::to_string(r.agent); });
  Status s = w.write(1, w.gripper, "open", Value(true));
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().code, ErrorCode::kRefused);
  EXPECT_NE(s.error().message.find("locked by agent100 (priority"), std::string::npos) << s.error().message;
  EXPECT_TRUE(w.write(1, w.person, "seen", Value(true)).ok()) << "outside the scope";
  EXPECT_TRUE(w.write(0, w.gripper, "open", Value(true)).ok()) << "the holder may write";
  EXPECT_FALSE(w.locks[1]->acquire(w.arm, 1).ok()) << "equal priority is refused";
  ASSERT_TRUE(w.locks[0]->release(w.arm).ok());
  w.advance(100'000'000);
  EXPECT_TRUE(w.write(1, w.gripper, "open", Value(false)).ok());
}

TEST(LocksTest, EqualPriorityRaceHasOneDeterministicWinner) {
  LockNet w(3);
  // Both claim before either hears of the other.
  ASSERT_TRUE(w.locks[0]->acquire(w.arm, 2).ok());
  ASSERT_TRUE(w.locks[1]->acquire(w.arm, 2).ok());
  w.advance(300'000'000);
  int holders = 0;
  for (auto& l : w.locks) holders += l->holds(w.arm) ? 1 : 0;
  EXPECT_EQ(holders, 1);
  auto w0 = w.locks[0]->winner(w.arm), w1 = w.locks[1]->winner(w.arm), w2 = w.locks[2]->winner(w.arm);
  ASSERT_TRUE(w0 && w1 && w2);
  EXPECT_EQ(w0->holder, w1->holder);
  EXPECT_EQ(w1->holder, w2->holder);
  int loser = w0->holder == w.net.nodes[0].g->replica() ? 1 : 0;
  EXPECT_TRUE(w.has(loser, LockEventKind::kLost)) << "the loser is told";
}

TEST(LocksTest, HigherPriorityPreemptsAndFencesTheOldHolder) {
  LockNet w(2);
  ASSERT_TRUE(w.locks[0]->acquire(w.arm, 1).ok());
  w.advance(200'000'000);
  ASSERT_TRUE(w.locks[0]->holds(w.arm));
  // Agent 1 preempts; agent 0 keeps writing before it hears (a stale holder).
  ASSERT_TRUE(w.locks[1]->acquire(w.arm, 5).ok());
  ASSERT_TRUE(w.write(1, w.arm, "goal", Value("home")).ok());
  w.net.inflight.clear();  // nothing has been delivered yet
  for (int i = 0; i < 5; ++i) ASSERT_TRUE(w.write(0, w.arm, "goal", Value("shelf " + std::to_string(i))).ok());
  w.advance(400'000'000);
  EXPECT_TRUE(w.locks[1]->holds(w.arm));
  EXPECT_FALSE(w.locks[0]->holds(w.arm));
  ASSERT_TRUE(w.has(0, LockEventKind::kLost));
  EXPECT_NE(w.events[0].back().reason.find("preempted"), std::string::npos) << w.events[0].back().reason;
  // The stale holder's later (in Lamport order) writes do not win: the new epoch's does.
  EXPECT_EQ(w.net.nodes[0].g->attr(w.arm, "goal")->as<std::string>().value(), "home");
  EXPECT_EQ(w.net.nodes[1].g->attr(w.arm, "goal")->as<std::string>().value(), "home");
  EXPECT_EQ(w.net.nodes[0].g->digest(), w.net.nodes[1].g->digest());
}

TEST(LocksTest, ACrashedHoldersLockExpires) {
  LockNet w(3, /*lease_ns=*/300'000'000);
  ASSERT_TRUE(w.locks[2]->acquire(w.arm, 3).ok());
  w.advance(200'000'000);
  ASSERT_TRUE(w.locks[2]->holds(w.arm));
  ASSERT_FALSE(w.locks[0]->acquire(w.arm, 1).ok());
  // Agent 2 dies silently.
  w.locks[2].reset();
  w.net.nodes[2].rep.reset();
  w.net.nodes[2].g.reset();
  w.advance(600'000'000);
  EXPECT_TRUE(w.has(0, LockEventKind::kExpired));
  ASSERT_TRUE(w.locks[0]->acquire(w.arm, 1).ok()) << "the expired lock is free again";
  w.advance(200'000'000);
  EXPECT_TRUE(w.locks[0]->holds(w.arm));
}

// A takeover from a crashed holder: its last write reached one peer but not the new claimant
// (a sample lost to one reader, whose writer died before it could resend it). The new claim is
// not held before the claimant holds that write too: it learns it from the peer that has it.
TEST(LocksTest, ATakeoverIsHeldOnlyOnceTheOldHoldersLastWritesAreHere) {
  LockNet w(3, /*lease_ns=*/300'000'000);
  ASSERT_TRUE(w.locks[2]->acquire(w.arm, 3).ok());
  w.advance(200'000'000);
  ASSERT_TRUE(w.locks[2]->holds(w.arm));
  // The holder's last write reaches agent 1 only.
  bool cut_from_1 = false;
  w.net.drop = [&](const Packet& f) {
    if (f.to != 0 || f.sample.topic == DdsTopic::kSummary) return false;
    return f.from == 2 || (f.from == 1 && cut_from_1);
  };
  ASSERT_TRUE(w.write(2, w.gripper, "goal", Value("shelf")).ok());
  w.net.advance(10'000'000, 1);
  ASSERT_TRUE(w.net.nodes[1].g->attr(w.gripper, "goal") != nullptr);
  ASSERT_EQ(w.net.nodes[0].g->attr(w.gripper, "goal"), nullptr);
  // Agent 2 dies; agent 1's deltas, pulls and states do not reach agent 0 for now (its
  // summaries do: it acknowledges claims and tells what it holds).
  w.locks[2].reset();
  w.net.nodes[2].rep.reset();
  w.net.nodes[2].g.reset();
  cut_from_1 = true;
  for (int i = 0; i < 40 && !w.has(0, LockEventKind::kExpired); ++i) w.advance(50'000'000);
  ASSERT_TRUE(w.has(0, LockEventKind::kExpired));
  ASSERT_EQ(w.net.nodes[0].g->attr(w.gripper, "goal"), nullptr) << "the test's cut did not hold";
  ASSERT_TRUE(w.locks[0]->acquire(w.arm, 1).ok());
  const std::uint64_t claim_seq = w.net.nodes[0].rep->last_seq();
  w.advance(300'000'000);
  // Every live peer acknowledged the claim: without the takeover rule it would be held now.
  ASSERT_TRUE(w.net.nodes[0].rep->all_peers_hold(w.net.nodes[0].g->replica(), claim_seq));
  EXPECT_FALSE(w.locks[0]->holds(w.arm)) << "held before the old holder's last write is here";
  EXPECT_FALSE(w.has(0, LockEventKind::kAcquired));
  // The cut heals: agent 0 gets the write from agent 1, then holds.
  cut_from_1 = false;
  for (int i = 0; i < 40 && !w.locks[0]->holds(w.arm); ++i) w.advance(50'000'000);
  EXPECT_TRUE(w.locks[0]->holds(w.arm));
  ASSERT_NE(w.net.nodes[0].g->attr(w.gripper, "goal"), nullptr);
  EXPECT_EQ(w.net.nodes[0].g->attr(w.gripper, "goal")->as<std::string>().value(), "shelf");
}

TEST(LocksTest, PartitionBothSidesHoldThenOneWinnerAfterHeal) {
  LockNet w(4, 300'000'000);
  // Split {0,1} | {2,3}.
  w.net.drop = [](const Packet& f) { return (f.from < 2) != (f.to < 2); };
  w.advance(600'000'000);  // each side notices the other left
  ASSERT_TRUE(w.locks[0]->acquire(w.arm, 2).ok());
  ASSERT_TRUE(w.locks[2]->acquire(w.arm, 2).ok());
  w.advance(300'000'000);
  EXPECT_TRUE(w.locks[0]->holds(w.arm)) << "availability: each side holds";
  EXPECT_TRUE(w.locks[2]->holds(w.arm));
  w.net.drop = nullptr;
  w.advance(800'000'000);
  EXPECT_NE(w.locks[0]->holds(w.arm), w.locks[2]->holds(w.arm)) << "exactly one winner after the heal";
  int loser = w.locks[0]->holds(w.arm) ? 2 : 0;
  ASSERT_TRUE(w.has(loser, LockEventKind::kLost));
  EXPECT_NE(w.events[loser].back().reason.find("concurrent claim"), std::string::npos) << w.events[loser].back().reason;
  for (int i = 1; i < 4; ++i) EXPECT_EQ(w.locks[i]->winner(w.arm)->holder, w.locks[0]->winner(w.arm)->holder);
}

TEST(LocksTest, DuplicatedAndReorderedLockMessagesChangeNothing) {
  LockNet w(3);
  ASSERT_TRUE(w.locks[0]->acquire(w.arm, 1).ok());
  ASSERT_TRUE(w.locks[1]->acquire(w.person, 1).ok());
  // Deliver everything twice, in reverse order.
  auto frames = w.net.inflight;
  w.net.inflight.clear();
  for (auto it = frames.rbegin(); it != frames.rend(); ++it) w.net.inflight.push_back(*it);
  for (const auto& f : frames) w.net.inflight.push_back(f);
  w.advance(300'000'000);
  EXPECT_TRUE(w.locks[0]->holds(w.arm));
  EXPECT_TRUE(w.locks[1]->holds(w.person));
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(w.locks[i]->winner(w.arm)->holder, w.net.nodes[0].g->replica());
    EXPECT_EQ(w.locks[i]->winner(w.person)->holder, w.net.nodes[1].g->replica());
  }
}

TEST(LocksTest, TwoAgentsNeedingTwoScopesDoNotDeadlock) {
  LockNet w(2);
  // Opposite orders of the same two scopes, at once: acquire_all claims in canonical order.
  Status a = w.locks[0]->acquire_all({w.arm, w.person}, 2);
  Status b = w.locks[1]->acquire_all({w.person, w.arm}, 2);
  ASSERT_TRUE(a.ok() && b.ok());
  w.advance(300'000'000);
  bool zero_both = w.locks[0]->holds(w.arm) && w.locks[0]->holds(w.person);
  bool one_both = w.locks[1]->holds(w.arm) && w.locks[1]->holds(w.person);
  EXPECT_TRUE(zero_both != one_both) << "one agent gets both scopes, none is stuck holding half";
  // The winner finishes and releases; the other then gets both.
  int winner = zero_both ? 0 : 1, other = 1 - winner;
  ASSERT_TRUE(w.locks[winner]->release(w.arm).ok());
  ASSERT_TRUE(w.locks[winner]->release(w.person).ok());
  w.advance(100'000'000);
  ASSERT_TRUE(w.locks[other]->acquire_all({w.arm, w.person}, 2).ok());
  w.advance(300'000'000);
  EXPECT_TRUE(w.locks[other]->holds(w.arm) && w.locks[other]->holds(w.person));
}

}  // namespace
}  // namespace quiver::agents

namespace quiver::agents {
namespace {

// Library code never commits inside a caller's transaction: acquire() and release() refuse while
// one is open (the claim would otherwise be committed in the middle of it), renewals wait.
TEST(LocksTest, NeverCommitsInsideACallersTransaction) {
  LockNet n(2);
  graph::Graph& g = *n.net.nodes[0].g;
  const std::size_t published = n.net.nodes[0].rep->last_seq();
  auto tx = g.begin();
  ASSERT_TRUE(tx.set(n.person, "seen", Value(true)).ok());
  Status s = n.locks[0]->acquire(n.arm, 5);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().code, ErrorCode::kRefused);
  EXPECT_NE(s.error().message.find("transaction is open"), std::string::npos) << s.error().message;
  EXPECT_EQ(n.net.nodes[0].rep->last_seq(), published) << "nothing was committed";
  ASSERT_TRUE(tx.commit().ok());
  EXPECT_TRUE(n.locks[0]->acquire(n.arm, 5).ok()) << "after the commit it goes through";
  n.advance(100'000'000);
  EXPECT_TRUE(n.locks[0]->holds(n.arm));
}

}  // namespace
}  // namespace quiver::agents
