// Property tests of the graph CRDT under random churn from several replicas at once:
//  - deltas delivered in random order, duplicated, or lost and replaced by state transfers,
//    all replicas converge to one digest;
//  - join of states is commutative, associative and idempotent;
//  - X ⊔ m^δ(X) = m(X): a commit's delta applied to a copy of the pre-commit state reproduces it;
//  - invariants hold on every replica after every step.

#include <gtest/gtest.h>

#include "graph_test_util.h"
#include "quiver/base/rng.h"
#include "quiver/sim/workload.h"
#include "test_seed.h"

namespace quiver::graph {
namespace {

using testing::Peer;

std::string first_violation(const Graph& g) {
  auto v = g.check_invariants();
  return v.empty() ? "" : v.front();
}

// Runs `steps` random transactions spread over `n` replicas; after each, a random subset of
// in-flight deltas is delivered (out of order, sometimes twice). Returns the replicas.
std::vector<std::unique_ptr<Peer>> churn(Rng& rng, int n, int steps, std::vector<std::vector<std::uint8_t>>* all) {
  std::vector<std::unique_ptr<Peer>> peers;
  for (int i = 0; i < n; ++i) peers.push_back(std::make_unique<Peer>(100 + i));
  sim::Churn work;
  std::vector<std::pair<int, std::vector<std::uint8_t>>> inflight;  // (origin, bytes)
  for (int s = 0; s < steps; ++s) {
    int who = static_cast<int>(rng.below(n));
    Peer& p = *peers[who];
    std::size_t before = p.outbox.size();
    work.step(p.g, rng, s * 1000);
    for (std::size_t i = before; i < p.outbox.size(); ++i) {
      inflight.emplace_back(who, p.outbox[i]);
      all->push_back(p.outbox[i]);
    }
    // Deliver a few random in-flight deltas to random replicas.
    for (int k = 0; k < 3 && !inflight.empty(); ++k) {
      std::size_t i = rng.below(inflight.size());
      int to = static_cast<int>(rng.below(n));
      if (to != inflight[i].first) peers[to]->receive(inflight[i].second);
      if (rng.chance(0.7)) {
        inflight[i] = inflight.back();
        inflight.pop_back();
      }
    }
    for (auto& q : peers) {
      std::string v = first_violation(q->g);
      EXPECT_EQ(v, "") << "step " << s;
      if (!v.empty()) return peers;
    }
  }
  return peers;
}

TEST(GraphPropertyTest, RandomDeliveryConverges) {
  const auto base = quiver::testing::base_seed("GraphPropertyTest.RandomDeliveryConverges", 500);
  for (int s = 0; s < quiver::testing::seed_count(150); ++s) {
    const std::uint64_t seed = base + s;
    Rng rng(seed);
    int n = 2 + static_cast<int>(rng.below(4));
    std::vector<std::vector<std::uint8_t>> all;
    auto peers = churn(rng, n, 60, &all);
    ASSERT_FALSE(HasFailure()) << "seed " << seed;
    // Every replica receives every delta, in its own random order, some twice.
    for (auto& p : peers) {
      auto order = all;
      for (int d = 0; d < 5 && !all.empty(); ++d) order.push_back(all[rng.below(all.size())]);
      rng.shuffle(order);
      for (const auto& m : order) {
        auto d = decode(m);
        ASSERT_TRUE(d.ok());
        if (d->origin != p->g.replica()) p->g.merge(*d);
      }
    }
    for (auto& p : peers) {
      ASSERT_EQ(first_violation(p->g), "") << "seed " << seed;
      ASSERT_EQ(p->g.digest(), peers[0]->g.digest()) << "seed " << seed;
      ASSERT_EQ(p->g.context(), peers[0]->g.context()) << "seed " << seed;
    }
  }
}

TEST(GraphPropertyTest, StateJoinIsCommutativeAssociativeIdempotent) {
  const auto base = quiver::testing::base_seed("GraphPropertyTest.StateJoinIsCommutativeAssociativeIdempotent", 900);
  for (int s = 0; s < quiver::testing::seed_count(100); ++s) {
    const std::uint64_t seed = base + s;
    Rng rng(seed);
    std::vector<std::vector<std::uint8_t>> all;
    auto peers = churn(rng, 3, 50, &all);
    ASSERT_FALSE(HasFailure()) << "seed " << seed;
    auto state = [&](int i) { return encode(peers[i]->g.state()); };
    auto fresh = [&](std::uint64_t id, std::vector<std::vector<std::uint8_t>> parts) {
      auto p = std::make_unique<Peer>(id);
      for (const auto& m : parts) p->receive(m);
      return p;
    };
    auto a = state(0), b = state(1), c = state(2);
    auto ab = fresh(900, {a, b}), ba = fresh(901, {b, a});
    ASSERT_EQ(ab->g.digest(), ba->g.digest()) << "commutative, seed " << seed;
    auto ab_c = fresh(902, {encode(ab->g.state()), c});
    auto bc = fresh(903, {b, c});
    auto a_bc = fresh(904, {a, encode(bc->g.state())});
    ASSERT_EQ(ab_c->g.digest(), a_bc->g.digest()) << "associative, seed " << seed;
    auto aa = fresh(905, {a, a});
    auto a1 = fresh(906, {a});
    ASSERT_EQ(aa->g.digest(), a1->g.digest()) << "idempotent, seed " << seed;
    ASSERT_EQ(a1->g.digest(), peers[0]->g.digest()) << "a state transfer reproduces the state, seed " << seed;
    // Context diffs: each replica catches up with every other through diffs only.
    for (auto& p : peers)
      for (auto& q : peers)
        if (p != q) p->receive_diff(*q);
    for (auto& p : peers) {
      ASSERT_EQ(p->g.digest(), peers[0]->g.digest()) << "diff convergence, seed " << seed;
      ASSERT_EQ(first_violation(p->g), "") << "seed " << seed;
    }
    ASSERT_EQ(peers[0]->g.digest(), fresh(907, {a, b, c})->g.digest()) << "diffs equal full merge, seed " << seed;
  }
}

TEST(GraphPropertyTest, DeltaOfACommitReproducesItOnACopy) {
  const auto base = quiver::testing::base_seed("GraphPropertyTest.DeltaOfACommitReproducesItOnACopy", 1300);
  for (int s = 0; s < quiver::testing::seed_count(100); ++s) {
    const std::uint64_t seed = base + s;
    Rng rng(seed);
    std::vector<std::vector<std::uint8_t>> all;
    auto peers = churn(rng, 2, 40, &all);
    ASSERT_FALSE(HasFailure()) << "seed " << seed;
    sim::Churn work;
    for (int k = 0; k < 10; ++k) {
      Peer& p = *peers[0];
      Peer copy(999);
      copy.receive_state(p);  // X
      std::size_t before = p.outbox.size();
      work.step(p.g, rng, 1000000 + k);  // m(X) on p
      for (std::size_t i = before; i < p.outbox.size(); ++i) copy.receive(p.outbox[i]);  // X ⊔ m^δ(X)
      ASSERT_EQ(copy.g.digest(), p.g.digest()) << "seed " << seed << " step " << k;
    }
  }
}

}  // namespace
}  // namespace quiver::graph
