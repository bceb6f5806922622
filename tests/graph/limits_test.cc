// The limits table (limits.h) holds at both ends: a change a local commit accepts decodes at every
// peer, and a change no decoder would accept is refused at the commit with an error naming it.
// Random sizes at, around and beyond every limit, for every place a name or a value enters.

#include <gtest/gtest.h>

#include <functional>

#include "graph_test_util.h"
#include "quiver/graph/limits.h"
#include "quiver/base/rng.h"
#include "test_seed.h"

namespace quiver::graph {
namespace {

using testing::Peer;

// One attempt: builds a change on a fresh replica through `make`, commits it, and requires either
// an error (from the call or the commit) or a delta and a state that another replica decodes.
struct Outcome {
  bool refused = false;
  std::string error;
};

Outcome attempt(const std::function<Status(Graph&, Transaction&)>& make) {
  Peer a(1);
  NodeId x = a.add("thing", "x"), y = a.add("thing", "y");
  {
    auto tx = a.g.begin();
    EXPECT_TRUE(tx.insert_edge(x, y, Symbol("e")).ok());
    EXPECT_TRUE(tx.commit().ok());
  }
  const std::size_t sent = a.outbox.size();
  const Digest128 before = a.g.digest();
  auto tx = a.g.begin();
  Status s = make(a.g, tx);
  Outcome out;
  if (s.ok()) {
    auto c = tx.commit();
    if (!c.ok()) s = c.error();
  }
  if (!s.ok()) {
    out.refused = true;
    out.error = s.error().message;
    EXPECT_FALSE(out.error.empty());
    EXPECT_EQ(a.g.digest(), before) << "a refused change leaves the replica as it was";
    EXPECT_EQ(a.outbox.size(), sent) << "a refused change publishes nothing";
    return out;
  }
  // Accepted: every peer must decode both the delta and a state that holds it.
  Peer b(2);
  for (const auto& m : a.outbox) {
    auto d = decode(m);
    EXPECT_TRUE(d.ok()) << "a committed delta does not decode: " << d.error().to_string();
    if (d.ok()) b.g.merge(*d);
  }
  auto st = decode(encode(a.g.state()));
  EXPECT_TRUE(st.ok()) << "the state does not decode: " << st.error().to_string();
  EXPECT_EQ(a.g.digest(), b.g.digest());
  return out;
}

std::size_t pick_size(Rng& rng, std::uint64_t limit) {
  switch (rng.below(6)) {
    case 0: return limit;
    case 1: return limit + 1;
    case 2: return limit - 1;
    case 3: return limit + 1 + rng.below(limit);
    case 4: return 0;
    default: return rng.below(limit + 1);
  }
}

std::string text(std::size_t n, Rng& rng) {
  std::string s(n, 'a');
  for (auto& c : s) c = static_cast<char>('a' + rng.below(26));
  return s;
}

TEST(LimitsTest, EveryNameAtAndBeyondTheLimitIsRefusedOrDecodes) {
  const auto base = quiver::testing::base_seed("LimitsTest.EveryNameAtAndBeyondTheLimitIsRefusedOrDecodes", 3);
  const int seeds = quiver::testing::seed_count(60);
  ASSERT_GT(seeds, 0) << "QUIVER_SEEDS must be positive";
  const std::uint64_t L = limits::kMaxNameBytes;
  int refused = 0, accepted = 0;
  for (int k = 0; k < seeds; ++k) {
    Rng rng(base + k);
    // Each place a name enters the graph.
    std::vector<std::pair<const char*, std::function<Status(Graph&, Transaction&, const std::string&)>>> sites = {
        {"node name", [](Graph&, Transaction& t, const std::string& s) { auto r = t.create_node("thing", s); return r.ok() ? Status{} : Status(r.error()); }},
        {"node type", [](Graph&, Transaction& t, const std::string& s) { auto r = t.create_node(s, "n"); return r.ok() ? Status{} : Status(r.error()); }},
        {"attribute name at creation", [](Graph&, Transaction& t, const std::string& s) {
           auto r = t.create_node("thing", "n", {{Symbol(s), Value(1.0)}});
           return r.ok() ? Status{} : Status(r.error());
         }},
        {"attribute name", [](Graph& g, Transaction& t, const std::string& s) { return t.set(*g.find_node("x"), s, Value(1.0)); }},
        {"edge type", [](Graph& g, Transaction& t, const std::string& s) { return t.insert_edge(*g.find_node("x"), *g.find_node("y"), s); }},
        {"edge attribute name at insertion", [](Graph& g, Transaction& t, const std::string& s) {
           return t.insert_edge(*g.find_node("y"), *g.find_node("x"), Symbol("f"), {{Symbol(s), Value(true)}});
         }},
        {"edge attribute name", [](Graph& g, Transaction& t, const std::string& s) {
           return t.set_edge_attr(EdgeKey{*g.find_node("x"), *g.find_node("y"), Symbol("e")}, Symbol(s), Value(2.0));
         }},
        {"rule name", [](Graph& g, Transaction& t, const std::string& s) {
           Status r = g.annotate_commit(s, {{"v", *g.find_node("x")}});
           return r.ok() ? t.set(*g.find_node("x"), "ruled", Value(true)) : r;
         }},
        {"rule variable", [](Graph& g, Transaction& t, const std::string& s) {
           Status r = g.annotate_commit("rule", {{s, *g.find_node("x")}});
           return r.ok() ? t.set(*g.find_node("x"), "ruled", Value(true)) : r;
         }},
    };
    for (auto& [site, make] : sites) {
      std::string name = text(pick_size(rng, L), rng);
      if (rng.chance(0.1) && !name.empty()) name[rng.below(name.size())] = static_cast<char>(0xff);  // not UTF-8
      Outcome o = attempt([&](Graph& g, Transaction& t) { return make(g, t, name); });
      const bool must_refuse = name.empty() || name.size() > L || !valid_utf8(name);
      EXPECT_EQ(o.refused, must_refuse) << site << " of " << name.size() << " bytes: " << o.error;
      if (o.refused && name.size() > L) EXPECT_NE(o.error.find("limit"), std::string::npos) << o.error;
      (o.refused ? refused : accepted)++;
    }
  }
  std::printf("[limits] names: %d accepted and decoded, %d refused\n", accepted, refused);
  EXPECT_GT(accepted, 0);
  EXPECT_GT(refused, 0);
}

TEST(LimitsTest, ValuesAtAndBeyondTheLimitAreRefusedOrDecode) {
  const std::uint64_t L = limits::kMaxValueBytes;
  struct Case {
    const char* what;
    std::size_t unit;
    std::function<Value(std::size_t)> make;
  };
  std::vector<Case> cases = {
      {"string", 1, [](std::size_t n) { return Value(std::string(n, 's')); }},
      {"bytes", 1, [](std::size_t n) { return Value(Bytes(n, 7)); }},
      {"float_vec", 4, [](std::size_t n) { return Value(FloatVec(n, 1.5f)); }},
      {"double_vec", 8, [](std::size_t n) { return Value(DoubleVec(n, 2.5)); }},
      {"uint64_vec", 8, [](std::size_t n) { return Value(UInt64Vec(n, 9)); }},
  };
  for (const Case& c : cases) {
    // Exactly at the limit travels (checked for one byte type and one vector type: each such
    // round trip copies 64 MiB a dozen times); one past it is refused for every type.
    std::vector<std::size_t> sizes = {L / c.unit + 1, std::size_t{3}};
    if (c.what == std::string("string") || c.what == std::string("float_vec")) sizes.push_back(L / c.unit);
    for (std::size_t n : sizes) {
      const bool must_refuse = n * c.unit > L;
      Outcome node = attempt([&](Graph& g, Transaction& t) { return t.set(*g.find_node("x"), "v", c.make(n)); });
      EXPECT_EQ(node.refused, must_refuse) << c.what << " of " << n << " elements on a node: " << node.error;
      if (must_refuse || n > 3) continue;
      Outcome edge = attempt([&](Graph& g, Transaction& t) {
        return t.insert_edge(*g.find_node("y"), *g.find_node("x"), Symbol("f"), {{Symbol("v"), c.make(n)}});
      });
      EXPECT_FALSE(edge.refused) << edge.error;
    }
  }
  // A value over the limit on an edge attribute is refused as well.
  Outcome big = attempt([&](Graph& g, Transaction& t) {
    return t.set_edge_attr(EdgeKey{*g.find_node("x"), *g.find_node("y"), Symbol("e")}, Symbol("v"), Value(std::string(L + 1, 'x')));
  });
  EXPECT_TRUE(big.refused);
  EXPECT_NE(big.error.find("limit"), std::string::npos) << big.error;
}

TEST(LimitsTest, ATransactionLargerThanADeltaMayBeIsRefused) {
  const std::uint64_t L = limits::kMaxValueBytes;
  Outcome o = attempt([&](Graph& g, Transaction& t) {
    NodeId x = *g.find_node("x");
    for (int i = 0; i < 4; ++i) {
      Status s = t.set(x, "v" + std::to_string(i), Value(std::string(L - 1, 'a')));
      if (!s.ok()) return s;
    }
    return Status{};
  });
  ASSERT_TRUE(o.refused) << "four values near the value limit exceed the delta limit";
  EXPECT_NE(o.error.find("commit it in parts"), std::string::npos) << o.error;
}

}  // namespace
}  // namespace quiver::graph
