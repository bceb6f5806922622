#include "quiver/crdt/causal_context.h"

#include <gtest/gtest.h>

#include <set>

#include "quiver/base/rng.h"
#include "test_seed.h"

namespace quiver::crdt {
namespace {

const ReplicaId kA{1, 1};
const ReplicaId kB{2, 1};

TEST(CausalContextTest, ContiguousDotsCompactIntoTheVersionVector) {
  CausalContext c;
  c.add(Dot{kA, 1});
  c.add(Dot{kA, 2});
  c.add(Dot{kA, 4});
  EXPECT_EQ(c.contiguous(kA), 2u);
  EXPECT_EQ(c.max_counter(kA), 4u);
  EXPECT_FALSE(c.contains(Dot{kA, 3}));
  EXPECT_EQ(c.range_count(), 2u);
  c.add(Dot{kA, 3});
  EXPECT_EQ(c.contiguous(kA), 4u);
  EXPECT_EQ(c.range_count(), 1u);
}

TEST(CausalContextTest, DotinLooksAtTheReplicaId) {
  CausalContext c;
  c.add_range(kA, 1, 10);
  EXPECT_TRUE(c.contains(Dot{kA, 5}));
  EXPECT_FALSE(c.contains(Dot{kB, 5}));
  EXPECT_FALSE(c.contains(Dot{ReplicaId{1, 2}, 5})) << "another incarnation of the same agent";
}

TEST(CausalContextTest, RangesMergeWhenAdjacentOrOverlapping) {
  CausalContext c;
  c.add_range(kA, 10, 20);
  c.add_range(kA, 30, 40);
  c.add_range(kA, 21, 29);
  EXPECT_EQ(c.range_count(), 1u);
  EXPECT_EQ(c.dot_count(), 31u);
  c.add_range(kA, 1, 9);
  EXPECT_EQ(c.contiguous(kA), 40u);
}

TEST(CausalContextTest, CountersUpToTheLastOne) {
  const std::uint64_t top = ~std::uint64_t{0};
  CausalContext c;
  c.add(Dot{kA, top - 2});
  c.add(Dot{kA, top - 1});
  c.add(Dot{kA, top});
  EXPECT_TRUE(c.contains(Dot{kA, top}));
  EXPECT_EQ(c.range_count(), 1u);
  c.add_range(kA, 1, 10);
  c.add_range(kA, 11, top - 3);
  EXPECT_EQ(c.contiguous(kA), top);
  CausalContext d;
  d.add_range(kA, top - 5, top);
  CausalContext e;
  e.add_range(kA, top - 3, top);
  EXPECT_EQ(d.minus(e).dot_count(), 2u);
  EXPECT_TRUE(e.minus(d).empty());
  EXPECT_TRUE(d.includes(e));
}

// A model check: random adds against std::set, with join / includes / minus.
TEST(CausalContextTest, MatchesASetModel) {
  const auto base = testing::base_seed("CausalContextTest.MatchesASetModel", 11);
  for (int s = 0; s < testing::seed_count(200); ++s) {
    Rng rng(base + s);
    CausalContext a, b;
    std::set<std::pair<int, std::uint64_t>> ma, mb;
    auto rep = [](int r) { return ReplicaId{static_cast<std::uint64_t>(r + 1), 1}; };
    for (int i = 0; i < 60; ++i) {
      int r = static_cast<int>(rng.below(3));
      std::uint64_t lo = 1 + rng.below(40), hi = lo + rng.below(5);
      auto& c = rng.chance(0.5) ? a : b;
      auto& m = (&c == &a) ? ma : mb;
      c.add_range(rep(r), lo, hi);
      for (auto x = lo; x <= hi; ++x) m.insert({r, x});
    }
    for (int r = 0; r < 3; ++r)
      for (std::uint64_t x = 1; x < 50; ++x) {
        ASSERT_EQ(a.contains(rep(r), x), ma.count({r, x}) == 1) << "seed " << base + s;
        ASSERT_EQ(b.contains(rep(r), x), mb.count({r, x}) == 1) << "seed " << base + s;
      }
    CausalContext d = a.minus(b);
    for (int r = 0; r < 3; ++r)
      for (std::uint64_t x = 1; x < 50; ++x)
        ASSERT_EQ(d.contains(rep(r), x), ma.count({r, x}) == 1 && mb.count({r, x}) == 0) << "seed " << base + s;
    CausalContext u = a;
    u.join(b);
    EXPECT_TRUE(u.includes(a));
    EXPECT_TRUE(u.includes(b));
    EXPECT_EQ(a.includes(b), std::includes(ma.begin(), ma.end(), mb.begin(), mb.end())) << "seed " << base + s;
    for (int r = 0; r < 3; ++r)
      for (std::uint64_t lo = 1; lo < 50; ++lo)
        for (std::uint64_t hi = lo; hi < lo + 8; ++hi) {
          bool all = true;
          for (auto x = lo; x <= hi; ++x) all = all && ma.count({r, x}) == 1;
          ASSERT_EQ(a.includes(rep(r), lo, hi), all)
              << "seed " << base + s << " range " << lo << ".." << hi;
        }
    CausalContext u2 = b;
    u2.join(a);
    EXPECT_EQ(u, u2);
    EXPECT_EQ(u.digest(), u2.digest());
  }
}

// Compaction must not be quadratic: 200k out-of-order dots, reversed, then filled.
TEST(CausalContextTest, CompactionOfManyGapsIsFast) {
  CausalContext c;
  const std::uint64_t n = 200000;
  for (std::uint64_t x = n; x >= 2; x -= 2) c.add(Dot{kA, x});
  EXPECT_EQ(c.range_count(), n / 2);
  for (std::uint64_t x = 1; x <= n; x += 2) c.add(Dot{kA, x});
  EXPECT_EQ(c.contiguous(kA), n);
  EXPECT_EQ(c.range_count(), 1u);
}

}  // namespace
}  // namespace quiver::crdt
