// Replicas agree: frame trees that follow merges (concurrent re-parenting, pose samples, deletes,
// deltas in any order, duplicated) match a fresh derivation, and every replica answers every
// lookup with the same bits — by hand-shipped deltas and in the deterministic simulator.

#include <gtest/gtest.h>

#include "kin_test_util.h"
#include "quiver/graph/codec.h"
#include "quiver/kinematics/frames.h"
#include "quiver/sim/simulator.h"
#include "test_seed.h"

namespace quiver::kinematics {
namespace {

using graph::Graph;
using graph::GraphDelta;
using graph::NodeId;
using graph::Pose;
using graph::ReplicaId;
using testing::in_subtree;
using testing::random_pose;

/// Every answer a replica gives, in a form that compares exactly: the 16 matrix entries, or the
/// error code.
struct Answer {
  bool ok = false;
  ErrorCode code = ErrorCode::kInternal;
  std::array<double, 16> m{};
  friend bool operator==(const Answer&, const Answer&) = default;
};

Answer answer(const Result<Eigen::Isometry3d>& r) {
  Answer a;
  a.ok = r.ok();
  if (!r.ok()) {
    a.code = r.error().code;
    return a;
  }
  for (int i = 0; i < 16; ++i) a.m[i] = r->matrix().data()[i];
  return a;
}

/// All pairs of `nodes`, now and at a few times, from one replica.
std::vector<Answer> all_answers(FrameTree& tree, const std::vector<NodeId>& nodes,
                                const std::vector<std::int64_t>& times) {
  std::vector<Answer> out;
  for (const NodeId& a : nodes)
    for (const NodeId& b : nodes) {
      out.push_back(answer(tree.lookup(a, b)));
      for (std::int64_t t : times) out.push_back(answer(tree.lookup_at(a, b, t)));
    }
  return out;
}

struct Replica {
  explicit Replica(std::uint64_t agent) : g(ReplicaId{agent, 1}) {
    g.set_delta_sink([this](const GraphDelta& d) { outbox.push_back(graph::encode(d)); });
    // No audit: the graph's change events alone must keep the tree equal to the graph.
    FrameTreeOptions events_only;
    events_only.audit_per_batch = 0;
    tree = std::make_unique<FrameTree>(g, events_only);
  }
  Graph g;
  std::vector<std::vector<std::uint8_t>> outbox;
  std::unique_ptr<FrameTree> tree;
};

/// One random transaction: moves (concurrent re-parenting when replicas do it at once), pose
/// samples, detaches, creations, deletions. At most one RT change per child and transaction.
void random_txn(Replica& r, Rng& rng, std::int64_t& now, int& names) {
  auto tx = r.g.begin();
  std::vector<NodeId> touched;
  const int ops = 1 + static_cast<int>(rng.below(3));
  for (int i = 0; i < ops; ++i) {
    auto live = r.g.nodes();
    const auto pick = rng.below(100);
    if (live.size() < 4 || pick < 10) {
      (void)tx.create_node(
          "f", "r" + std::to_string(r.g.replica().agent) + "_" + std::to_string(names++));
      continue;
    }
    NodeId c = rng.pick(live);
    if (std::find(touched.begin(), touched.end(), c) != touched.end()) continue;
    touched.push_back(c);
    if (pick < 55) {
      NodeId p = rng.pick(live);
      if (!(p == c) && !in_subtree(r.g, c, p)) (void)tx.set_rt(p, c, random_pose(rng), now += 7);
    } else if (pick < 90) {
      if (auto p = r.g.rt_parent(c)) (void)tx.set_rt(*p, c, random_pose(rng), now += 7);
    } else if (pick < 95) {
      (void)tx.remove_rt(c);
    } else {
      (void)tx.delete_node(c);
    }
  }
  ASSERT_TRUE(tx.commit().ok());
}

TEST(FramesReplicationTest, FollowersMatchAndReplicasAgreeAfterMerges) {
  const std::uint64_t base =
      quiver::testing::base_seed("FramesReplicationTest.FollowersMatch", 9001);
  const int seeds = quiver::testing::seed_count(20);
  for (int k = 0; k < seeds; ++k) {
    const std::uint64_t seed = base + k;
    SCOPED_TRACE("seed " + std::to_string(seed));
    Rng rng(seed);
    std::vector<std::unique_ptr<Replica>> reps;
    for (int i = 0; i < 3; ++i) reps.push_back(std::make_unique<Replica>(10 + i));
    // A common start: a world and a few frames everyone has.
    {
      auto tx = reps[0]->g.begin();
      NodeId w = *tx.create_node("world", "world");
      for (int i = 0; i < 6; ++i) {
        NodeId f = *tx.create_node("f", "s" + std::to_string(i));
        ASSERT_TRUE(tx.set_rt(w, f, random_pose(rng), 1).ok());
      }
      ASSERT_TRUE(tx.commit().ok());
    }
    std::int64_t now = 10;
    int names = 0;
    std::vector<std::size_t> delivered(3 * 3, 0);  // [to * 3 + from]: outbox prefix delivered
    int stale = 0, checks = 0;
    auto deliver_some = [&](int to) {
      // Deltas from each other replica, a random number of them, sometimes out of order and
      // duplicated.
      for (int from = 0; from < 3; ++from) {
        if (from == to) continue;
        auto& out = reps[from]->outbox;
        std::size_t& done = delivered[to * 3 + from];
        if (done >= out.size()) continue;
        std::size_t upto = done + 1 + rng.below(out.size() - done);
        std::vector<std::size_t> order;
        for (std::size_t i = done; i < upto; ++i) order.push_back(i);
        rng.shuffle(order);
        if (rng.chance(0.3)) order.push_back(order.front());
        for (std::size_t i : order) {
          auto d = graph::decode(out[i]);
          ASSERT_TRUE(d.ok());
          reps[to]->g.merge(*d);
        }
        done = upto;
        // The events of the merges keep the tree equal to the graph; a stale frame is counted
        // (and the test fails at the end), then a full audit repairs it so the run goes on.
        if (!reps[to]->tree->check_against_graph().empty()) ++stale;
        reps[to]->tree->audit(1 << 20);
        auto diffs = reps[to]->tree->check_against_graph();
        ASSERT_TRUE(diffs.empty()) << "replica " << to << ": " << diffs.front();
        ++checks;
      }
    };
    // Everyone starts from the common state.
    deliver_some(1);
    deliver_some(2);
    for (int round = 0; round < 40; ++round) {
      for (int i = 0; i < 3; ++i) random_txn(*reps[i], rng, now, names);
      deliver_some(static_cast<int>(rng.below(3)));
    }
    // Deliver everything everywhere (twice round: deltas whose causal past arrived later).
    for (int pass = 0; pass < 2; ++pass)
      for (int to = 0; to < 3; ++to)
        for (int from = 0; from < 3; ++from) {
          if (from == to) continue;
          for (const auto& m : reps[from]->outbox) {
            auto d = graph::decode(m);
            ASSERT_TRUE(d.ok());
            reps[to]->g.merge(*d);
          }
        }
    ASSERT_EQ(reps[0]->g.digest(), reps[1]->g.digest());
    ASSERT_EQ(reps[0]->g.digest(), reps[2]->g.digest());
    for (auto& r : reps) {
      if (!r->tree->check_against_graph().empty()) ++stale;
      ++checks;
      r->tree->audit(1 << 20);
      auto diffs = r->tree->check_against_graph();
      ASSERT_TRUE(diffs.empty()) << diffs.front();
    }
    const auto nodes = reps[0]->g.nodes();
    const std::vector<std::int64_t> times{0, now / 3, now / 2, now - 20, now};
    const auto a0 = all_answers(*reps[0]->tree, nodes, times);
    EXPECT_EQ(a0, all_answers(*reps[1]->tree, nodes, times));
    EXPECT_EQ(a0, all_answers(*reps[2]->tree, nodes, times));
    // Not vacuous: some lookups succeed, some timed ones are refused.
    EXPECT_GT(std::count_if(a0.begin(), a0.end(), [](const Answer& a) { return a.ok; }), 10);
    // Events do all the work: no merge may leave a frame the graph did not announce.
    EXPECT_EQ(stale, 0) << "of " << checks << " merges (replay with this seed)";
  }
}

TEST(FramesReplicationTest, SimulatedConcurrentReparentingKeepsLookupsEqual) {
  const std::uint64_t base = quiver::testing::base_seed("FramesReplicationTest.Simulated", 31337);
  const int seeds = quiver::testing::seed_count(10);
  for (int k = 0; k < seeds; ++k) {
    sim::SimConfig cfg;
    cfg.seed = base + k;
    cfg.agents = 5;
    cfg.steps = 150;
    cfg.faults.loss = 0.1;
    cfg.faults.dup = 0.05;
    cfg.faults.reorder = true;
    cfg.faults.partitions = k % 2 == 1;
    // Heavy in re-parenting and pose samples.
    cfg.mix.rt_move = 14;
    cfg.mix.rt_pose = 10;
    cfg.mix.rt_remove = 1;
    cfg.mix.set_attr = 2;
    cfg.mix.insert_edge = 1;
    cfg.mix.max_nodes = 25;
    std::size_t compared = 0, ok_answers = 0, frames = 0;
    cfg.inspect = [&](const std::vector<const Graph*>& graphs) {
      std::vector<std::vector<Answer>> answers;
      const auto nodes = graphs[0]->nodes();
      frames = nodes.size();
      // The replicated times at which samples exist (the simulator stamps with virtual ns).
      std::vector<std::int64_t> times{0};
      for (const NodeId& n : nodes)
        for (const auto& s : graphs[0]->rt_history(n))
          if (times.size() < 8) times.push_back(s.stamp + 1);
      for (const Graph* g : graphs) {
        FrameTree tree(*g);  // a snapshot: the simulator owns the graphs
        answers.push_back(all_answers(tree, nodes, times));
      }
      for (std::size_t i = 1; i < answers.size(); ++i) {
        ASSERT_EQ(answers[i].size(), answers[0].size());
        for (std::size_t j = 0; j < answers[0].size(); ++j) {
          ASSERT_TRUE(answers[i][j] == answers[0][j]) << "replica " << i << " answer " << j;
          ++compared;
        }
      }
      for (const Answer& a : answers[0]) ok_answers += a.ok;
    };
    sim::SimResult r = sim::run_simulation(cfg);
    ASSERT_TRUE(r.ok()) << r.to_json();
    EXPECT_GT(compared, 0u) << "seed " << cfg.seed;
    EXPECT_GT(ok_answers, frames) << "seed " << cfg.seed;  // more than the identities
  }
}

}  // namespace
}  // namespace quiver::kinematics
