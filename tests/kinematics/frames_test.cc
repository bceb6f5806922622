// FrameTree lookups against direct matrix products, on random trees changed by random
// transactions; timed lookups against a reference interpolation; the error values.

#include "quiver/kinematics/frames.h"

#include <gtest/gtest.h>

#include "kin_test_util.h"
#include "quiver/graph/codec.h"
#include "quiver/graph/world_file.h"
#include "test_seed.h"

namespace quiver::kinematics {
namespace {

using graph::Graph;
using graph::NodeId;
using graph::Pose;
using graph::ReplicaId;
using testing::in_subtree;
using testing::iso;
using testing::max_abs_diff;
using testing::random_pose;
using testing::ref_lookup_at;
using testing::ref_root_pose;

constexpr double kTol = 1e-9;

/// Checks every ordered pair of visible nodes: lookups by name, by id and by handle, from the
/// owner and from a reader, against the reference.
void check_all_pairs(const Graph& g, FrameTree& tree, FrameReader& reader, const std::string& ctx) {
  auto nodes = g.nodes();
  for (const NodeId& a : nodes) {
    auto [ra, X_RA] = ref_root_pose(g, a);
    for (const NodeId& b : nodes) {
      auto [rb, X_RB] = ref_root_pose(g, b);
      auto got = tree.lookup(g.name_of(a), g.name_of(b));
      if (!(ra == rb)) {
        ASSERT_FALSE(got.ok()) << ctx;
        ASSERT_EQ(got.error().code, ErrorCode::kNotConnected)
            << ctx << " " << got.error().to_string();
        continue;
      }
      ASSERT_TRUE(got.ok()) << ctx << " " << got.error().to_string();
      Eigen::Isometry3d want = X_RA.inverse() * X_RB;
      ASSERT_LT(max_abs_diff(*got, want), kTol)
          << ctx << " " << g.name_of(a) << " -> " << g.name_of(b);
      auto by_id = reader.lookup(a, b);
      ASSERT_TRUE(by_id.ok()) << by_id.error().to_string();
      ASSERT_EQ(by_id->matrix(), got->matrix()) << ctx;  // same table, same arithmetic
    }
  }
}

TEST(FramesTest, RandomTreesMatchMatrixProducts) {
  const std::uint64_t base =
      quiver::testing::base_seed("FramesTest.RandomTreesMatchMatrixProducts", 4242);
  const int seeds = quiver::testing::seed_count(30);
  for (int k = 0; k < seeds; ++k) {
    const std::uint64_t seed = base + k;
    SCOPED_TRACE("seed " + std::to_string(seed));
    Rng rng(seed);
    Graph g(ReplicaId{1, 1});
    // No audit: every update must come from the graph's change events.
    FrameTreeOptions no_audit;
    no_audit.audit_per_batch = 0;
    FrameTree tree(g, no_audit);
    FrameReader reader = tree.reader();
    std::vector<NodeId> ids;
    int next_name = 0;
    std::int64_t now = 0;
    for (int step = 0; step < 60; ++step) {
      auto tx = g.begin();
      const int ops = 1 + static_cast<int>(rng.below(4));
      // Several RT changes of one child in one transaction (move, sample, detach) are allowed.
      auto first_touch = [](NodeId) { return true; };
      for (int i = 0; i < ops; ++i) {
        auto live = g.nodes();
        const auto pick = rng.below(100);
        if (live.size() < 3 || pick < 20) {
          auto id = tx.create_node("thing", "n" + std::to_string(next_name++));
          if (id.ok()) ids.push_back(*id);
        } else if (pick < 50) {  // move under a random node outside the subtree
          NodeId c = rng.pick(live), p = rng.pick(live);
          if (c == p || in_subtree(g, c, p) || !first_touch(c)) continue;
          (void)tx.set_rt(p, c, random_pose(rng), ++now);
        } else if (pick < 80) {  // pose sample
          NodeId c = rng.pick(live);
          if (!first_touch(c)) continue;
          if (auto p = g.rt_parent(c)) (void)tx.set_rt(*p, c, random_pose(rng), ++now);
        } else if (pick < 90) {
          NodeId c = rng.pick(live);
          if (first_touch(c)) (void)tx.remove_rt(c);
        } else {
          (void)tx.delete_node(rng.pick(live));
        }
      }
      ASSERT_TRUE(tx.commit().ok());
      auto diffs = tree.check_against_graph();
      ASSERT_TRUE(diffs.empty()) << "step " << step << ": " << diffs.front();
      check_all_pairs(g, tree, reader, "step " + std::to_string(step));
    }
    EXPECT_GT(tree.stats().publishes, 0u);
  }
}

// Once a graph bug: a transaction that detached a child and re-attached it under the same parent
// with a new pose raised no RT event, so no follower could see the new transform.
TEST(FramesTest, DetachAndReattachInOneTransaction) {
  Graph g(ReplicaId{1, 1});
  NodeId w, c;
  {
    auto tx = g.begin();
    w = *tx.create_node("world", "world");
    c = *tx.create_node("f", "c");
    ASSERT_TRUE(tx.set_rt(w, c, Pose{{1, 0, 0}, {1, 0, 0, 0}}).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  FrameTreeOptions no_audit;  // the event alone must carry the change
  no_audit.audit_per_batch = 0;
  FrameTree tree(g, no_audit);
  {
    auto tx = g.begin();
    ASSERT_TRUE(tx.remove_rt(c).ok());
    ASSERT_TRUE(tx.set_rt(w, c, Pose{{2, 0, 0}, {1, 0, 0, 0}}).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  auto diffs = tree.check_against_graph();
  EXPECT_TRUE(diffs.empty()) << diffs.front();
}

// A late sample of the parent a child had before its move can still be newer than the oldest
// sample kept; it then evicts a sample of the current parent from the bounded history, which
// changes what a timed lookup answers. The graph must announce that.
TEST(FramesTest, ALateSampleOfTheOldParentEvictingACurrentOneIsAnnounced) {
  Graph a(ReplicaId{1, 1}), b(ReplicaId{2, 1});
  std::vector<std::vector<std::uint8_t>> from_a, from_b;
  a.set_delta_sink([&](const graph::GraphDelta& d) { from_a.push_back(graph::encode(d)); });
  b.set_delta_sink([&](const graph::GraphDelta& d) { from_b.push_back(graph::encode(d)); });
  NodeId p1, p2, c;
  {
    auto tx = a.begin();
    NodeId w = *tx.create_node("world", "world");
    p1 = *tx.create_node("f", "p1");
    p2 = *tx.create_node("f", "p2");
    c = *tx.create_node("f", "c");
    ASSERT_TRUE(tx.set_rt(w, p1, Pose{{1, 0, 0}, {1, 0, 0, 0}}).ok());
    ASSERT_TRUE(tx.set_rt(w, p2, Pose{{0, 1, 0}, {1, 0, 0, 0}}).ok());
    ASSERT_TRUE(tx.set_rt(p1, c, Pose{{0, 0, 1}, {1, 0, 0, 0}}, 1).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  for (const auto& m : from_a) {
    auto d = graph::decode(m);
    ASSERT_TRUE(d.ok());
    b.merge(*d);
  }
  // b, not yet aware of any move, samples c under p1 at t = 100.
  {
    auto tx = b.begin();
    ASSERT_TRUE(tx.set_rt(p1, c, Pose{{0, 0, 5}, {1, 0, 0, 0}}, 100).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  FrameTreeOptions no_audit;  // the event alone must carry the change
  no_audit.audit_per_batch = 0;
  FrameTree tree(a, no_audit);
  // a moves c under p2 at t = 10 and fills the history with samples of that parent.
  for (std::int64_t t = 10; t < 10 + static_cast<std::int64_t>(graph::kRtHistoryDepth); ++t) {
    auto tx = a.begin();
    ASSERT_TRUE(tx.set_rt(p2, c, Pose{{0, 0, static_cast<double>(t)}, {1, 0, 0, 0}}, t).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  ASSERT_EQ(a.rt_history(c).size(), graph::kRtHistoryDepth);
  ASSERT_EQ(a.rt_history(c).front().stamp, 10);
  ASSERT_TRUE(tree.check_against_graph().empty());
  const auto before = tree.lookup_at("p2", "c", 10);
  ASSERT_TRUE(before.ok()) << before.error().message;
  // b's sample arrives: the t = 10 sample of p2 is evicted, so t = 10 is no longer covered.
  for (const auto& m : from_b) {
    auto d = graph::decode(m);
    ASSERT_TRUE(d.ok());
    a.merge(*d);
  }
  ASSERT_EQ(*a.rt_parent(c), p2);
  ASSERT_EQ(a.rt_history(c).front().stamp, 11);
  auto diffs = tree.check_against_graph();
  EXPECT_TRUE(diffs.empty()) << diffs.front();
  EXPECT_FALSE(tree.lookup_at("p2", "c", 10).ok());
}

TEST(FramesTest, OnlyTheChangedSubtreeIsRecomputed) {
  Graph g(ReplicaId{1, 1});
  std::vector<NodeId> a, b;
  {
    auto tx = g.begin();
    NodeId w = *tx.create_node("world", "world");
    NodeId pa = w, pb = w;
    for (int i = 0; i < 10; ++i) {
      a.push_back(*tx.create_node("f", "a" + std::to_string(i)));
      b.push_back(*tx.create_node("f", "b" + std::to_string(i)));
      ASSERT_TRUE(tx.set_rt(pa, a.back(), Pose{{1, 0, 0}, {1, 0, 0, 0}}).ok());
      ASSERT_TRUE(tx.set_rt(pb, b.back(), Pose{{0, 1, 0}, {1, 0, 0, 0}}).ok());
      pa = a.back();
      pb = b.back();
    }
    ASSERT_TRUE(tx.commit().ok());
  }
  FrameTree tree(g);
  auto v_b9 = tree.reader().pose_version("b9");
  const auto before = tree.stats().pose_recomputes;
  {
    auto tx = g.begin();
    ASSERT_TRUE(tx.set_rt(a[4], a[5], Pose{{2, 0, 0}, {1, 0, 0, 0}}, 5).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  // a5..a9: five cache entries, nothing on branch b.
  EXPECT_EQ(tree.stats().pose_recomputes - before, 5u);
  EXPECT_EQ(*tree.reader().pose_version("b9"), *v_b9);
  auto X = tree.lookup("world", "a9");
  ASSERT_TRUE(X.ok());
  EXPECT_NEAR(X->translation().x(), 11.0, 1e-12);
}

TEST(FramesTest, TimedLookupsInterpolateAndRefuseExtrapolation) {
  const std::uint64_t base = quiver::testing::base_seed("FramesTest.TimedLookups", 77);
  const int seeds = quiver::testing::seed_count(20);
  for (int k = 0; k < seeds; ++k) {
    const std::uint64_t seed = base + k;
    SCOPED_TRACE("seed " + std::to_string(seed));
    Rng rng(seed);
    Graph g(ReplicaId{1, 1});
    FrameTree tree(g);
    auto reader = tree.reader();
    std::vector<NodeId> ids;
    {
      auto tx = g.begin();
      ids.push_back(*tx.create_node("world", "world"));
      for (int i = 1; i < 12; ++i) {
        ids.push_back(*tx.create_node("f", "f" + std::to_string(i)));
        ASSERT_TRUE(tx.set_rt(ids[rng.below(i)], ids.back(), random_pose(rng), 0).ok());
      }
      ASSERT_TRUE(tx.commit().ok());
    }
    // Samples at random stamps in [100, 1000], more than the history keeps on some edges.
    for (int s = 0; s < 200; ++s) {
      auto tx = g.begin();
      NodeId c = ids[1 + rng.below(ids.size() - 1)];
      ASSERT_TRUE(tx.set_rt(*g.rt_parent(c), c, random_pose(rng),
                            100 + static_cast<std::int64_t>(rng.below(901)))
                      .ok());
      ASSERT_TRUE(tx.commit().ok());
    }
    int ok = 0, refused = 0;
    for (int q = 0; q < 400; ++q) {
      NodeId a = rng.pick(ids), b = rng.pick(ids);
      const std::int64_t t = static_cast<std::int64_t>(rng.below(1200));
      auto want = ref_lookup_at(g, a, b, t);
      auto got = reader.lookup_at(a, b, t);
      if (want) {
        ASSERT_TRUE(got.ok()) << "t=" << t << ": " << got.error().to_string();
        ASSERT_LT(max_abs_diff(*got, *want), kTol) << "t=" << t;
        ++ok;
      } else {
        ASSERT_FALSE(got.ok()) << "t=" << t;
        ASSERT_EQ(got.error().code, ErrorCode::kExtrapolation) << got.error().to_string();
        ++refused;
      }
    }
    EXPECT_GT(ok, 0);
    EXPECT_GT(refused, 0);
  }
}

TEST(FramesTest, ErrorsSayWhatWentWrong) {
  Graph g(ReplicaId{1, 1});
  NodeId arm, table;
  {
    auto tx = g.begin();
    NodeId w = *tx.create_node("world", "world");
    arm = *tx.create_node("arm", "arm");
    table = *tx.create_node("table", "table");
    NodeId mug = *tx.create_node("mug", "mug");
    ASSERT_TRUE(tx.set_rt(w, arm, Pose{}, 10).ok());
    ASSERT_TRUE(tx.set_rt(table, mug, Pose{}, 10).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  {
    auto tx = g.begin();
    ASSERT_TRUE(tx.set_rt(*g.find_node("world"), arm, Pose{{1, 0, 0}, {1, 0, 0, 0}}, 20).ok());
    ASSERT_TRUE(tx.set_rt(*g.find_node("world"), arm, Pose{{2, 0, 0}, {1, 0, 0, 0}}, 30).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  FrameTree tree(g);

  auto r = tree.lookup("world", "gripper");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, ErrorCode::kNotFound);
  EXPECT_NE(
      r.error().message.find("lookup(): \"gripper\" passed to lookup() as frame B does not exist"),
      std::string::npos)
      << r.error().message;

  r = tree.lookup("", "world");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, ErrorCode::kInvalidArgument);
  EXPECT_NE(r.error().message.find("frame names cannot be empty"), std::string::npos)
      << r.error().message;

  r = tree.lookup("arm", "mug");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, ErrorCode::kNotConnected);
  EXPECT_NE(r.error().message.find(
                "Could not find a connection between \"arm\" and \"mug\" because they are not "
                "part of the same tree"),
            std::string::npos)
      << r.error().message;

  // The move at t=10 is the first sample of the edge's history.
  r = tree.lookup_at("world", "arm", 5);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, ErrorCode::kExtrapolation);
  EXPECT_NE(r.error().message.find(
                "extrapolation into the past. Requested time 5 but the earliest data is at "
                "time 10"),
            std::string::npos)
      << r.error().message;
  r = tree.lookup_at("world", "arm", 31);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find(
                "extrapolation into the future. Requested time 31 but the latest data is at "
                "time 30"),
            std::string::npos)
      << r.error().message;
  r = tree.lookup_at("world", "arm", 25);
  ASSERT_TRUE(r.ok()) << r.error().to_string();
  EXPECT_NEAR(r->translation().x(), 1.5, 1e-12);

  // A handle goes stale when its node is deleted.
  Frame h = *tree.frame("table");
  ASSERT_TRUE(tree.lookup(h, "mug").ok());
  {
    auto tx = g.begin();
    ASSERT_TRUE(tx.delete_node(table).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  r = tree.lookup(h, "mug");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, ErrorCode::kNotFound);
  EXPECT_FALSE(tree.frame("table").ok());
  // The mug is now a root of its own.
  auto root = tree.root_pose("mug");
  ASSERT_TRUE(root.ok());
  EXPECT_EQ(root->first, *tree.frame("mug"));

  // Points and poses in another frame.
  auto p = tree.transform_point("world", "arm", Eigen::Vector3d(0, 0, 1));
  ASSERT_TRUE(p.ok());
  EXPECT_NEAR((*p - Eigen::Vector3d(2, 0, 1)).norm(), 0.0, 1e-12);
  auto p_at = tree.transform_point("world", "arm", Eigen::Vector3d(0, 0, 1), 25);
  ASSERT_TRUE(p_at.ok());
  EXPECT_NEAR((*p_at - Eigen::Vector3d(1.5, 0, 1)).norm(), 0.0, 1e-12);
}

TEST(FramesTest, InterpolationNeverCrossesAChangeOfParent) {
  Graph g(ReplicaId{1, 1});
  NodeId w, p1, p2, c;
  {
    auto tx = g.begin();
    w = *tx.create_node("world", "world");
    p1 = *tx.create_node("f", "p1");
    p2 = *tx.create_node("f", "p2");
    c = *tx.create_node("f", "c");
    ASSERT_TRUE(tx.set_rt(w, p1, Pose{{1, 0, 0}, {1, 0, 0, 0}}).ok());
    ASSERT_TRUE(tx.set_rt(w, p2, Pose{{0, 1, 0}, {1, 0, 0, 0}}).ok());
    ASSERT_TRUE(tx.set_rt(p1, c, Pose{}, 0).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  auto sample = [&](NodeId parent, double x, std::int64_t t) {
    auto tx = g.begin();
    ASSERT_TRUE(tx.set_rt(parent, c, Pose{{x, 0, 0}, {1, 0, 0, 0}}, t).ok());
    ASSERT_TRUE(tx.commit().ok());
  };
  FrameTree tree(g);
  sample(p1, 0.0, 10);
  sample(p1, 1.0, 20);
  ASSERT_TRUE(tree.lookup_at("world", "c", 15).ok());
  // The move to p2 at t = 30 starts a new epoch: nothing before it can be answered.
  sample(p2, 5.0, 30);
  auto r = tree.lookup_at("world", "c", 15);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, ErrorCode::kExtrapolation);
  EXPECT_NE(r.error().message.find("earliest data is at time 30"), std::string::npos)
      << r.error().message;
  r = tree.lookup_at("world", "c", 35);  // one sample: constant from its stamp on
  ASSERT_TRUE(r.ok());
  EXPECT_NEAR(r->translation().x(), 5.0, 1e-12);
  sample(p2, 6.0, 40);
  sample(p2, 8.0, 50);
  r = tree.lookup_at("world", "c", 45);
  ASSERT_TRUE(r.ok());
  EXPECT_NEAR(r->translation().x(), 7.0, 1e-12);
  EXPECT_NEAR(r->translation().y(), 1.0, 1e-12);
  // Samples of the old epoch written concurrently (same stamps range) are ignored.
  auto range = tree.edge_time_range("c");
  ASSERT_TRUE(range.ok());
  EXPECT_EQ(range->second, 50);
}

TEST(FramesTest, NamesFollowNamesakesAndDeletions) {
  Graph a(ReplicaId{1, 1}), b(ReplicaId{2, 1});
  std::vector<graph::GraphDelta> from_a, from_b;
  a.set_delta_sink([&](const graph::GraphDelta& d) { from_a.push_back(d); });
  b.set_delta_sink([&](const graph::GraphDelta& d) { from_b.push_back(d); });
  FrameTree ta(a), tb(b);
  // Both replicas create "mug" concurrently.
  {
    auto tx = a.begin();
    ASSERT_TRUE(tx.create_node("mug", "mug").ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  {
    auto tx = b.begin();
    ASSERT_TRUE(tx.create_node("mug", "mug").ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  for (auto& d : from_a) b.merge(d);
  for (auto& d : from_b) a.merge(d);
  EXPECT_TRUE(ta.check_against_graph().empty());
  EXPECT_TRUE(tb.check_against_graph().empty());
  auto winner = *a.find_node("mug");
  EXPECT_EQ(*ta.reader().node("mug"), winner);
  EXPECT_EQ(*tb.reader().node("mug"), winner);
  for (const NodeId& id : a.namesakes("mug")) {
    EXPECT_EQ(*ta.reader().node(a.name_of(id)), id);
    EXPECT_EQ(*ta.reader().name(id), a.name_of(id));
  }
  // Deleting the winner gives the name back to the other one.
  from_a.clear();
  {
    auto tx = a.begin();
    ASSERT_TRUE(tx.delete_node(winner).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  for (auto& d : from_a) b.merge(d);
  EXPECT_TRUE(ta.check_against_graph().empty());
  EXPECT_TRUE(tb.check_against_graph().empty());
  EXPECT_EQ(*tb.reader().node("mug"), *b.find_node("mug"));
  EXPECT_FALSE(winner == *b.find_node("mug"));
}

TEST(FramesTest, WorldFileFramesAndRpy) {
  Graph g(ReplicaId{1, 1});
  auto info = graph::load_world(g, R"({"quiver_world": 1,
    "nodes": [{"name": "world", "type": "world"}, {"name": "base", "type": "robot"},
              {"name": "cam", "type": "camera"}],
    "rt": [{"parent": "world", "child": "base", "translation": [1, 2, 0], "rpy": [0, 0, 1.5707963267948966]},
           {"parent": "base", "child": "cam", "translation": [0.5, 0, 1], "rotation": [1, 0, 0, 0]}]})");
  ASSERT_TRUE(info.ok()) << info.error().to_string();
  FrameTree tree(g);
  auto X = tree.lookup("world", "cam");
  ASSERT_TRUE(X.ok());
  // The camera is 0.5 m along the base's x axis, which points along world y.
  EXPECT_NEAR((X->translation() - Eigen::Vector3d(1, 2.5, 1)).norm(), 0.0, 1e-12);
  auto p = tree.transform_point("cam", "world", Eigen::Vector3d(1, 2.5, 1));
  ASSERT_TRUE(p.ok());
  EXPECT_NEAR(p->norm(), 0.0, 1e-12);
}

}  // namespace
}  // namespace quiver::kinematics
