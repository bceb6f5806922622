// Transactions open at the same time: every interleaving either commits correctly (its changes
// reach every replica and stay there) or is refused with an error naming the change that no
// longer applies. Random interleavings are checked against replicas fed only through the codec.

#include <gtest/gtest.h>

#include "graph_test_util.h"
#include "quiver/base/rng.h"
#include "test_seed.h"

namespace quiver::graph {
namespace {

using testing::Peer;

// The case of the issue: T1 creates a node, T2 commits, T1 commits. The node must reach another
// replica, later writes to it too, and survive state exchanges in both directions.
TEST(TransactionTest, ANodeCreatedBeforeAnotherCommitReplicates) {
  Peer a(1), b(2);
  NodeId other = a.add("thing", "other");
  auto t1 = a.g.begin();
  NodeId mug = *t1.create_node("mug", "mug");
  {
    auto t2 = a.g.begin();
    ASSERT_TRUE(t2.set(other, "x", Value(1.0)).ok());
    ASSERT_TRUE(t2.commit().ok());
  }
  ASSERT_TRUE(t1.commit().ok());
  b.receive_all(a);
  ASSERT_TRUE(b.g.has_node(mug)) << "the node reaches the other replica";
  {
    auto tx = a.g.begin();
    ASSERT_TRUE(tx.set(mug, "full", Value(true)).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  b.receive_all(a);
  ASSERT_NE(b.g.attr(mug, "full"), nullptr) << "later writes to it reach the other replica";
  b.receive_state(a);
  a.receive_state(b);
  EXPECT_TRUE(a.g.has_node(mug)) << "a state exchange does not delete it at its origin";
  EXPECT_TRUE(b.g.has_node(mug));
  EXPECT_EQ(a.g.digest(), b.g.digest());
  EXPECT_TRUE(a.g.check_invariants().empty());
}

TEST(TransactionTest, AWriteToANodeDeletedMeanwhileIsRefusedWhole) {
  Peer a(1);
  NodeId n = a.add("thing", "n");
  NodeId m = a.add("thing", "m");
  auto t1 = a.g.begin();
  ASSERT_TRUE(t1.set(m, "y", Value(2.0)).ok());
  ASSERT_TRUE(t1.set(n, "x", Value(1.0)).ok());
  {
    auto t2 = a.g.begin();
    ASSERT_TRUE(t2.delete_node(n).ok());
    ASSERT_TRUE(t2.commit().ok());
  }
  const std::size_t sent = a.outbox.size();
  auto r = t1.commit();
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, ErrorCode::kNotFound);
  EXPECT_NE(r.error().message.find("no longer applies"), std::string::npos) << r.error().message;
  EXPECT_EQ(a.g.attr(m, "y"), nullptr) << "nothing of the refused transaction was applied";
  EXPECT_EQ(a.outbox.size(), sent) << "nothing was published";
}

TEST(TransactionTest, ANameTakenMeanwhileIsRefused) {
  Peer a(1);
  auto t1 = a.g.begin();
  ASSERT_TRUE(t1.create_node("mug", "mug").ok());
  auto t2 = a.g.begin();
  ASSERT_TRUE(t2.create_node("mug", "mug").ok()) << "each transaction sees only the committed graph";
  ASSERT_TRUE(t2.commit().ok());
  auto r = t1.commit();
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, ErrorCode::kAlreadyExists) << r.error().message;
  EXPECT_EQ(a.g.namesakes("mug").size(), 1u) << "never two local nodes of one name";
}

TEST(TransactionTest, AnAbandonedTransactionLeavesNoHoleInTheContext) {
  Peer a(1), b(2);
  {
    auto t1 = a.g.begin();
    ASSERT_TRUE(t1.create_node("x", "never").ok());
    a.add("y", "kept");  // commits while t1 holds its node id
  }  // t1 is discarded: its id was never published
  a.add("z", "later");
  b.receive_all(a);
  EXPECT_EQ(a.g.digest(), b.g.digest()) << "the skipped counter went out with the next commit";
  EXPECT_EQ(a.g.context().range_count(), 1u) << "the context stays one contiguous range";
}

// Random transactions held open across each other's commits, committed in random order; the
// replica that receives only the deltas must end equal to the origin.
TEST(TransactionTest, RandomInterleavingsReplicateExactly) {
  const auto base = quiver::testing::base_seed("TransactionTest.RandomInterleavingsReplicateExactly", 5);
  const int seeds = quiver::testing::seed_count(200);
  ASSERT_GT(seeds, 0) << "QUIVER_SEEDS must be positive";
  int committed = 0, refused = 0;
  for (int k = 0; k < seeds; ++k) {
    Rng rng(base + k);
    Peer a(1), b(2);
    std::vector<NodeId> nodes;
    for (int i = 0; i < 4; ++i) nodes.push_back(a.add("t", "seed" + std::to_string(i)));
    std::vector<Transaction> open;
    int names = 0;
    for (int step = 0; step < 60; ++step) {
      if (open.empty() || rng.chance(0.35)) open.push_back(a.g.begin());
      Transaction& tx = open[rng.below(open.size())];
      switch (rng.below(6)) {
        case 0: {
          auto id = tx.create_node("t", rng.chance(0.3) ? "shared" : "n" + std::to_string(names++));
          if (id.ok()) nodes.push_back(*id);
          break;
        }
        case 1: (void)tx.delete_node(rng.pick(nodes)); break;
        case 2: (void)tx.insert_edge(rng.pick(nodes), rng.pick(nodes), Symbol("e")); break;
        case 3: (void)tx.set_rt(rng.pick(nodes), rng.pick(nodes), Pose{}, step); break;
        default: (void)tx.set(rng.pick(nodes), "v", Value(static_cast<std::int64_t>(step))); break;
      }
      if (rng.chance(0.3)) {
        std::size_t i = rng.below(open.size());
        if (rng.chance(0.1)) {
          open[i].abort();
        } else {
          auto r = open[i].commit();
          if (r.ok()) ++committed;
          else ++refused;
          if (!r.ok()) EXPECT_FALSE(r.error().message.empty());
        }
        open.erase(open.begin() + static_cast<long>(i));
      }
      ASSERT_TRUE(a.g.check_invariants().empty()) << "replay with QUIVER_SEED=" << base + k;
    }
    for (auto& tx : open) {
      auto r = tx.commit();
      if (r.ok()) ++committed;
      else ++refused;
    }
    open.clear();
    a.add("t", "last");  // publishes whatever abandoned transactions skipped
    b.receive_all(a);
    ASSERT_EQ(a.g.digest(), b.g.digest()) << "replay with QUIVER_SEED=" << base + k;
    b.receive_state(a);
    a.receive_state(b);
    ASSERT_EQ(a.g.digest(), b.g.digest()) << "replay with QUIVER_SEED=" << base + k;
    for (NodeId n : a.g.nodes()) ASSERT_TRUE(b.g.has_node(n));
  }
  std::printf("[interleavings] %d seeds: %d commits, %d refused as stale\n", seeds, committed, refused);
  EXPECT_GT(committed, 0);
  EXPECT_GT(refused, 0) << "some interleavings must conflict, or the test checks nothing";
}

}  // namespace
}  // namespace quiver::graph

namespace quiver::graph {
namespace {

// Defect 10: the cycle error named nodes created in the same transaction as "".
TEST(TransactionTest, ACycleErrorNamesNodesCreatedInTheTransaction) {
  Peer a(1);
  auto tx = a.g.begin();
  NodeId arm = *tx.create_node("link", "arm"), hand = *tx.create_node("link", "hand");
  ASSERT_TRUE(tx.set_rt(arm, hand, Pose{}).ok());
  Status s = tx.set_rt(hand, arm, Pose{});
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().message.find("'arm'"), std::string::npos) << s.error().message;
  EXPECT_NE(s.error().message.find("'hand'"), std::string::npos) << s.error().message;
}

}  // namespace
}  // namespace quiver::graph
