// Property tests of the dot-store CRDTs: join is commutative, associative and idempotent;
// X ⊔ m^δ(X) = m(X) for every mutator; deltas joined in any order, duplicated or re-sent, give
// the same state as merging full states.

#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <string>

#include "quiver/crdt/types.h"
#include "quiver/base/rng.h"
#include "test_seed.h"

namespace quiver::crdt {
namespace {

using Reg = MVReg<int>;
using Set = AWSet<int>;
// A map of registers and a map of sets: nested stores sharing one context.
using RegMap = ORMap<std::string, DotFun<int>>;
using SetMap = ORMap<std::string, DotMap<int, DotSet>>;

ReplicaId rep(int i) { return ReplicaId{static_cast<std::uint64_t>(100 + i), 7}; }

// One random mutation of a replica of type T: the delta, plus a check of what m(X) must look
// like according to the type's sequential specification (independent of the join).
template <class T>
struct Ops;

template <class State>
using Check = std::function<bool(const State& before, const State& after)>;

template <>
struct Ops<Reg> {
  using State = Reg::State;
  static State mutate(const State& x, ReplicaId r, Rng& rng, Check<State>* check = nullptr) {
    if (rng.chance(0.15)) {
      if (check) *check = [](const State&, const State& y) { return Reg::values(y).empty(); };
      return Reg::clear(x);
    }
    int v = static_cast<int>(rng.below(100));
    if (check) *check = [v](const State&, const State& y) { return Reg::values(y) == std::vector<int>{v}; };
    return Reg::write(x, r, v);
  }
};
template <>
struct Ops<Set> {
  using State = Set::State;
  static State mutate(const State& x, ReplicaId r, Rng& rng, Check<State>* check = nullptr) {
    int e = static_cast<int>(rng.below(6));
    bool add = rng.chance(0.6);
    if (check)
      *check = [e, add](const State& b, const State& y) {
        auto want = Set::elements(b);
        if (add && !Set::contains(b, e)) want.push_back(e);
        if (!add) want.erase(std::remove(want.begin(), want.end(), e), want.end());
        std::sort(want.begin(), want.end());
        return Set::elements(y) == want;
      };
    return add ? Set::add(x, r, e) : Set::remove(x, e);
  }
};
template <>
struct Ops<RegMap> {
  using State = RegMap::State;
  static std::vector<int> at(const State& y, const std::string& k) {
    std::vector<int> out;
    if (const auto* f = RegMap::get(y, k))
      for (const auto& e : *f) out.push_back(e.value);
    return out;
  }
  static State mutate(const State& x, ReplicaId r, Rng& rng, Check<State>* check = nullptr) {
    std::string k = "k" + std::to_string(rng.below(4));
    if (rng.chance(0.2)) {
      if (check) *check = [k](const State&, const State& y) { return RegMap::get(y, k) == nullptr; };
      return RegMap::remove(x, k);
    }
    int v = static_cast<int>(rng.below(50));
    if (check)
      *check = [k, v](const State& b, const State& y) {
        // The key now holds exactly v; every other key is untouched.
        if (at(y, k) != std::vector<int>{v}) return false;
        for (const auto& [key, f] : b.store)
          if (key != k && at(y, key) != at(b, key)) return false;
        return true;
      };
    return RegMap::apply(x, k, [&](const Causal<DotFun<int>>& inner) { return Reg::write(inner, r, v); });
  }
};
template <>
struct Ops<SetMap> {
  using State = SetMap::State;
  static std::vector<int> at(const State& y, const std::string& k) {
    std::vector<int> out;
    if (const auto* m = SetMap::get(y, k))
      for (const auto& [e, dots] : *m) out.push_back(e);
    return out;
  }
  static State mutate(const State& x, ReplicaId r, Rng& rng, Check<State>* check = nullptr) {
    std::string k = "s" + std::to_string(rng.below(3));
    if (rng.chance(0.15)) {
      if (check) *check = [k](const State&, const State& y) { return SetMap::get(y, k) == nullptr; };
      return SetMap::remove(x, k);
    }
    int e = static_cast<int>(rng.below(4));
    bool add = rng.chance(0.6);
    if (check)
      *check = [k, e, add](const State& b, const State& y) {
        auto want = at(b, k);
        if (add && std::find(want.begin(), want.end(), e) == want.end()) want.push_back(e);
        if (!add) want.erase(std::remove(want.begin(), want.end(), e), want.end());
        std::sort(want.begin(), want.end());
        return at(y, k) == want;
      };
    return SetMap::apply(x, k, [&](const Causal<DotMap<int, DotSet>>& inner) {
      return add ? Set::add(inner, r, e) : Set::remove(inner, e);
    });
  }
};

template <class T>
class CrdtLaws : public ::testing::Test {};
using Types = ::testing::Types<Reg, Set, RegMap, SetMap>;
TYPED_TEST_SUITE(CrdtLaws, Types);

// Three replicas evolve concurrently, exchanging random deltas; returns their states and the log
// of every delta produced.
template <class T>
struct Run {
  using State = typename Ops<T>::State;
  std::vector<State> replicas;
  std::vector<State> deltas;
};

template <class T>
Run<T> random_run(Rng& rng, int nrep, int steps) {
  Run<T> run;
  run.replicas.resize(nrep);
  for (int i = 0; i < steps; ++i) {
    int r = static_cast<int>(rng.below(nrep));
    auto d = Ops<T>::mutate(run.replicas[r], rep(r), rng);
    auto expected = join(run.replicas[r], d);
    run.replicas[r].join(d);
    EXPECT_EQ(run.replicas[r], expected);
    EXPECT_TRUE(run.replicas[r].well_formed());
    run.deltas.push_back(d);
    // Occasionally ship a random earlier delta to a random replica (out of order, duplicated).
    if (rng.chance(0.5)) {
      int to = static_cast<int>(rng.below(nrep));
      run.replicas[to].join(run.deltas[rng.below(run.deltas.size())]);
    }
  }
  return run;
}

TYPED_TEST(CrdtLaws, JoinIsCommutativeAssociativeIdempotent) {
  const auto base = testing::base_seed("CrdtLaws.JoinIsCommutativeAssociativeIdempotent", 1000);
  for (int s = 0; s < testing::seed_count(300); ++s) {
    Rng rng(base + s);
    auto run = random_run<TypeParam>(rng, 3, 30);
    const auto& a = run.replicas[0];
    const auto& b = run.replicas[1];
    const auto& c = run.replicas[2];
    ASSERT_EQ(join(a, b), join(b, a)) << "seed " << base + s;
    ASSERT_EQ(join(join(a, b), c), join(a, join(b, c))) << "seed " << base + s;
    ASSERT_EQ(join(a, a), a) << "seed " << base + s;
    ASSERT_TRUE(join(a, b).well_formed()) << "seed " << base + s;
  }
}

TYPED_TEST(CrdtLaws, DeltaMutatorsMatchFullMutation) {
  // X ⊔ m^δ(X) = m(X): the join of X with the delta must show exactly the effect the type's
  // sequential specification gives m(X), and the delta must be an inflation that re-joins to
  // nothing new.
  const auto base = testing::base_seed("CrdtLaws.DeltaMutatorsMatchFullMutation", 2000);
  for (int s = 0; s < testing::seed_count(300); ++s) {
    Rng rng(base + s);
    auto run = random_run<TypeParam>(rng, 2, 25);
    for (int k = 0; k < 5; ++k) {
      auto x = run.replicas[k % 2];
      Check<typename Ops<TypeParam>::State> check;
      auto d = Ops<TypeParam>::mutate(x, rep(k % 2), rng, &check);
      auto mx = join(x, d);
      ASSERT_TRUE(check(x, mx)) << "seed " << base + s << " step " << k;
      ASSERT_TRUE(mx.well_formed()) << "seed " << base + s;
      ASSERT_TRUE(mx.ctx.includes(x.ctx)) << "seed " << base + s;
      ASSERT_EQ(join(mx, d), mx) << "seed " << base + s;
      ASSERT_EQ(join(mx, x), mx) << "m(X) is an inflation of X, seed " << base + s;
    }
  }
}

TYPED_TEST(CrdtLaws, DeltasInAnyOrderDuplicatedEqualFullStateMerge) {
  const auto base = testing::base_seed("CrdtLaws.DeltasInAnyOrderDuplicatedEqualFullStateMerge", 3000);
  for (int s = 0; s < testing::seed_count(300); ++s) {
    Rng rng(base + s);
    auto run = random_run<TypeParam>(rng, 3, 30);
    typename Ops<TypeParam>::State full;
    for (const auto& r : run.replicas) full.join(r);
    // Every replica's state is the join of some of the deltas, so all deltas joined in a random
    // order, with duplicates, must equal the join of the full states.
    auto order = run.deltas;
    for (int dup = 0; dup < 10; ++dup) order.push_back(run.deltas[rng.below(run.deltas.size())]);
    rng.shuffle(order);
    typename Ops<TypeParam>::State fromDeltas;
    for (const auto& d : order) fromDeltas.join(d);
    ASSERT_EQ(fromDeltas, full) << "seed " << base + s;
  }
}

TEST(MVRegTest, ConcurrentWritesAreAllKeptAndTheWinnerIsDeterministic) {
  Reg::State a, b;
  a.join(Reg::write(a, rep(1), 10));
  b.join(a);
  auto da = Reg::write(a, rep(1), 11);
  auto db = Reg::write(b, rep(2), 22);
  a.join(da);
  b.join(db);
  a.join(db);
  b.join(da);
  ASSERT_EQ(a, b);
  EXPECT_EQ(Reg::values(a).size(), 2u);
  EXPECT_EQ(Reg::winner(a)->value, Reg::winner(b)->value);
  // A later write supersedes both.
  a.join(Reg::write(a, rep(1), 33));
  EXPECT_EQ(Reg::values(a), std::vector<int>{33});
}

TEST(AWSetTest, AddWinsOverConcurrentRemove) {
  Set::State a, b;
  a.join(Set::add(a, rep(1), 5));
  b.join(a);
  auto rm = Set::remove(a, 5);
  auto add = Set::add(b, rep(2), 5);
  a.join(rm);
  b.join(add);
  a.join(add);
  b.join(rm);
  EXPECT_TRUE(Set::contains(a, 5));
  EXPECT_EQ(a, b);
}

}  // namespace
}  // namespace quiver::crdt
