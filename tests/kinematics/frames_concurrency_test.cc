// Readers on other threads while the owner thread commits: every answer is consistent (no torn
// reads across a batch), names come and go safely, and replaced memory is freed once readers
// move on. Not a timing test: it checks values, not speeds.

#include <gtest/gtest.h>

#include <atomic>
#include <mutex>
#include <thread>

#include "kin_test_util.h"
#include "quiver/kinematics/frames.h"
#include "test_seed.h"

namespace quiver::kinematics {
namespace {

using graph::Graph;
using graph::NodeId;
using graph::Pose;
using graph::ReplicaId;
using testing::iso;
using testing::max_abs_diff;
using testing::random_pose;

/// X_WD = X_WC · K as a graph pose.
Pose times(const Pose& X_WC, const Pose& K) {
  Eigen::Isometry3d X_WD = iso(X_WC) * iso(K);
  Eigen::Quaterniond q(X_WD.linear());
  Pose p;
  p.translation = {X_WD.translation().x(), X_WD.translation().y(), X_WD.translation().z()};
  p.rotation = {q.w(), q.x(), q.y(), q.z()};
  return p;
}

TEST(FramesConcurrencyTest, ReadersSeeWholeBatchesOnly) {
  const std::uint64_t seed =
      quiver::testing::base_seed("FramesConcurrencyTest.ReadersSeeWholeBatchesOnly", 5150);
  Rng rng(seed);
  Graph g(ReplicaId{1, 1});
  NodeId w, m, a, b, c, d;
  const Pose X_MA = random_pose(rng), X_MB = random_pose(rng), K = random_pose(rng);
  {
    auto tx = g.begin();
    w = *tx.create_node("world", "world");
    m = *tx.create_node("f", "m");
    a = *tx.create_node("f", "a");
    b = *tx.create_node("f", "b");
    c = *tx.create_node("f", "c");
    d = *tx.create_node("f", "d");
    ASSERT_TRUE(tx.set_rt(w, m, random_pose(rng), 0).ok());
    ASSERT_TRUE(tx.set_rt(m, a, X_MA, 0).ok());
    ASSERT_TRUE(tx.set_rt(m, b, X_MB, 0).ok());
    const Pose X_WC = random_pose(rng);
    ASSERT_TRUE(tx.set_rt(w, c, X_WC, 0).ok());
    ASSERT_TRUE(tx.set_rt(w, d, times(X_WC, K), 0).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  // X_AB never changes (only m moves above them). X_CD = K holds after every transaction, which
  // moves c and d together — a reader that mixed two batches would see something else.
  const Eigen::Isometry3d want_AB = iso(X_MA).inverse() * iso(X_MB);
  const Eigen::Isometry3d want_CD = iso(K);
  FrameTree tree(g);
  std::atomic<bool> stop{false};
  std::atomic<long> lookups{0}, bad{0}, timed_ok{0};
  std::atomic<std::int64_t> latest_stamp{0};
  std::string first_bad;
  std::mutex bad_mu;
  auto report = [&](const std::string& what) {
    if (bad.fetch_add(1) == 0) {
      std::lock_guard lock(bad_mu);
      first_bad = what;
    }
  };
  auto reader_fn = [&](int id) {
    FrameReader r = tree.reader();
    Rng local(seed + 100 + id);
    long n = 0;
    while (!stop.load(std::memory_order_relaxed)) {
      auto ab = r.lookup("a", "b");
      if (!ab.ok() || max_abs_diff(*ab, want_AB) > 1e-9)
        report("X_AB " + (ab.ok() ? std::string("wrong") : ab.error().message));
      auto cd = r.lookup(c, d);
      if (!cd.ok() || max_abs_diff(*cd, want_CD) > 1e-9)
        report("X_CD " + (cd.ok() ? std::string("wrong") : cd.error().message));
      // At the exact stamp of a sample, both edges hold the poses of one transaction.
      const std::int64_t t = latest_stamp.load(std::memory_order_relaxed) -
                             1000 * static_cast<std::int64_t>(local.below(8));
      if (t > 0) {
        auto cdt = r.lookup_at("c", "d", t);
        if (cdt.ok()) {
          timed_ok.fetch_add(1, std::memory_order_relaxed);
          if (max_abs_diff(*cdt, want_CD) > 1e-9) report("X_CD at " + std::to_string(t) + " wrong");
        } else if (cdt.error().code != ErrorCode::kExtrapolation) {
          report("X_CD at t: " + cdt.error().message);
        }
      }
      // Names that come and go: a result or a clean error, never a crash.
      auto tmp = r.lookup("world", "tmp" + std::to_string(local.below(4)));
      if (!tmp.ok() && tmp.error().code != ErrorCode::kNotFound &&
          tmp.error().code != ErrorCode::kNotConnected)
        report("tmp: " + tmp.error().message);
      n += 4;
    }
    lookups.fetch_add(n);
  };
  std::thread r1(reader_fn, 1), r2(reader_fn, 2);
  // The owner thread: 6000 transactions.
  std::int64_t stamp = 0;
  std::vector<NodeId> tmp;
  for (int i = 0; i < 6000; ++i) {
    auto tx = g.begin();
    stamp += 1000;
    ASSERT_TRUE(tx.set_rt(w, m, random_pose(rng), stamp).ok());
    const Pose X_WC = random_pose(rng);
    ASSERT_TRUE(tx.set_rt(w, c, X_WC, stamp).ok());
    ASSERT_TRUE(tx.set_rt(w, d, times(X_WC, K), stamp).ok());
    if (i % 7 == 0) {
      // Churn names: create or delete a temporary frame.
      if (tmp.size() < 4) {
        auto id = tx.create_node("tmp", "tmp" + std::to_string(rng.below(4)));
        if (id.ok()) {
          ASSERT_TRUE(tx.set_rt(w, *id, random_pose(rng), stamp).ok());
          tmp.push_back(*id);
        }
      } else {
        ASSERT_TRUE(tx.delete_node(tmp.front()).ok());
        tmp.erase(tmp.begin());
      }
    }
    ASSERT_TRUE(tx.commit().ok());
    latest_stamp.store(stamp, std::memory_order_relaxed);
    // Let the readers run between batches too (this is about interleavings, not throughput).
    if (i % 8 == 0) std::this_thread::sleep_for(std::chrono::microseconds(50));
  }
  stop.store(true);
  r1.join();
  r2.join();
  EXPECT_EQ(bad.load(), 0) << first_bad;
  EXPECT_GT(lookups.load(), 1000);
  EXPECT_GT(timed_ok.load(), 0);
  // Readers are gone: the next publish frees everything they might have seen.
  {
    auto tx = g.begin();
    ASSERT_TRUE(tx.create_node("tmp", "last").ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  EXPECT_EQ(tree.stats().retired_pending, 0u);
  EXPECT_GT(tree.stats().publishes, 6000u);
  std::printf("  %ld lookups, %ld timed, during 6000 batches\n", lookups.load(), timed_ok.load());
}

TEST(FramesConcurrencyTest, IdleReaderDelaysReclamationButNeverBlocks) {
  Graph g(ReplicaId{1, 1});
  FrameTree tree(g);
  FrameReader r = tree.reader();
  {
    auto tx = g.begin();
    ASSERT_TRUE(tx.create_node("f", "x").ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  ASSERT_TRUE(r.frame("x").ok());  // r announces the current epoch and then stays silent
  // Renaming-by-deletion replaces published names: they must wait for r.
  for (int i = 0; i < 10; ++i) {
    auto tx = g.begin();
    ASSERT_TRUE(tx.create_node("f", "y" + std::to_string(i)).ok());
    ASSERT_TRUE(tx.delete_node(*g.find_node(i == 0 ? "x" : "y" + std::to_string(i - 1))).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  EXPECT_GT(tree.stats().retired_pending, 0u);
  // Once r moves on (or goes idle), the next update frees them.
  r.idle();
  {
    auto tx = g.begin();
    ASSERT_TRUE(tx.create_node("f", "z").ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  EXPECT_EQ(tree.stats().retired_pending, 0u);
  // An idle reader still answers (it comes back online on its next call).
  EXPECT_TRUE(r.frame("z").ok());
  EXPECT_FALSE(r.frame("x").ok());
}

TEST(FramesConcurrencyTest, ReadersOutliveTheirTree) {
  Graph g(ReplicaId{1, 1});
  {
    auto tx = g.begin();
    NodeId w = *tx.create_node("world", "world");
    NodeId x = *tx.create_node("f", "x");
    ASSERT_TRUE(tx.set_rt(w, x, Pose{{1, 2, 3}, {1, 0, 0, 0}}).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  std::optional<FrameReader> r;
  {
    FrameTree tree(g);
    r.emplace(tree.reader());
  }
  // The graph changes; the tree is gone and does not follow. The reader keeps the last state.
  {
    auto tx = g.begin();
    ASSERT_TRUE(
        tx.set_rt(*g.find_node("world"), *g.find_node("x"), Pose{{9, 9, 9}, {1, 0, 0, 0}}).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  auto X = r->lookup("world", "x");
  ASSERT_TRUE(X.ok());
  EXPECT_EQ(X->translation(), Eigen::Vector3d(1, 2, 3));
}

}  // namespace
}  // namespace quiver::kinematics
