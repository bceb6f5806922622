#include "quiver/graph/codec.h"

#include <gtest/gtest.h>

#include "graph_test_util.h"
#include "quiver/base/rng.h"
#include "quiver/sim/workload.h"
#include "test_seed.h"

namespace quiver::graph {
namespace {

using testing::Peer;

std::vector<std::vector<std::uint8_t>> sample_messages(std::uint64_t seed) {
  Peer p(5);
  Rng rng(seed);
  sim::Churn churn;
  for (int i = 0; i < 60; ++i) churn.step(p.g, rng, i * 10);
  auto out = p.outbox;
  out.push_back(encode(p.g.state()));
  return out;
}

TEST(CodecTest, EveryValueTypeRoundTrips) {
  Peer a(1), b(2);
  auto tx = a.g.begin();
  std::vector<std::pair<Symbol, Value>> attrs = {
      {Symbol("s"), Value("text")},
      {Symbol("b"), Value(true)},
      {Symbol("i32"), Value::int32(-5)},
      {Symbol("i64"), Value(std::int64_t{-1} << 40)},
      {Symbol("u32"), Value::uint32(4000000000u)},
      {Symbol("u64"), Value(~std::uint64_t{0})},
      {Symbol("f"), Value(1.5f)},
      {Symbol("d"), Value(-2.25)},
      {Symbol("bytes"), Value(Bytes{0, 1, 2, 255})},
      {Symbol("fv"), Value(FloatVec{1, 2, 3})},
      {Symbol("dv"), Value(DoubleVec{1e-300, 2})},
      {Symbol("uv"), Value(UInt64Vec{1, ~0ull})},
      {Symbol("v2"), Value(Vec2f{1, 2})},
      {Symbol("v3"), Value(Vec3f{1, 2, 3})},
      {Symbol("v4"), Value(Vec4f{1, 2, 3, 4})},
      {Symbol("v6"), Value(Vec6f{1, 2, 3, 4, 5, 6})},
      {Symbol("m"), Value(Mat4d::identity())},
  };
  auto id = tx.create_node("thing", "all", attrs);
  ASSERT_TRUE(id.ok());
  ASSERT_TRUE(tx.commit().ok());
  b.receive_all(a);
  for (const auto& [name, v] : attrs) {
    const Value* got = b.g.attr(*id, name);
    ASSERT_NE(got, nullptr) << name.str();
    EXPECT_EQ(*got, v) << name.str();
    EXPECT_EQ(got->type(), v.type());
  }
  EXPECT_EQ(a.g.digest(), b.g.digest());
}

TEST(CodecTest, ReEncodingIsStable) {
  for (const auto& m : sample_messages(3)) {
    auto d = decode(m);
    ASSERT_TRUE(d.ok()) << d.error().to_string();
    EXPECT_EQ(encode(*d), m);
  }
}

TEST(CodecTest, EveryTruncationIsAnErrorAndChangesNothing) {
  for (const auto& m : sample_messages(4)) {
    Peer target(9);
    target.add("thing", "keep");
    Digest128 before = target.g.digest();
    for (std::size_t n = 0; n < m.size(); ++n) {
      GraphDelta d;
      Status s = decode(std::span<const std::uint8_t>(m.data(), n), d);
      ASSERT_FALSE(s.ok()) << "a prefix of " << n << " of " << m.size() << " bytes decoded";
      EXPECT_TRUE(s.error().code == ErrorCode::kTruncated || s.error().code == ErrorCode::kMalformed ||
                  s.error().code == ErrorCode::kTooLarge)
          << s.error().to_string();
      EXPECT_NE(s.error().message.find("byte"), std::string::npos) << "errors say where: " << s.error().message;
    }
    EXPECT_EQ(target.g.digest(), before);
  }
}

TEST(CodecTest, VersionTrailingBytesAndLimits) {
  auto m = sample_messages(5).front();
  auto next = m;
  next[2] = kCodecVersion + 1;
  auto r = decode(next);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, ErrorCode::kUnsupportedVersion);
  EXPECT_NE(r.error().message.find("version " + std::to_string(kCodecVersion + 1)), std::string::npos)
      << r.error().message;
  auto trailing = m;
  trailing.push_back(0);
  r = decode(trailing);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("trailing"), std::string::npos) << r.error().message;
  // A string value over the configured limit is refused before anything is allocated.
  Peer a(1);
  auto tx = a.g.begin();
  ASSERT_TRUE(tx.create_node("thing", "big", {{Symbol("blob"), Value(std::string(5000, 'x'))}}).ok());
  ASSERT_TRUE(tx.commit().ok());
  DecodeLimits small;
  small.max_value_bytes = 1000;
  r = decode(a.outbox.back(), small);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, ErrorCode::kTooLarge);
  EXPECT_TRUE(decode(a.outbox.back()).ok());
}

TEST(CodecTest, CorruptedMessagesNeverBreakAReplica) {
  const auto base = quiver::testing::base_seed("CodecTest.CorruptedMessagesNeverBreakAReplica", 31);
  Rng rng(base);
  auto msgs = sample_messages(base);
  int accepted = 0;
  for (int i = 0; i < 3000; ++i) {
    auto m = rng.pick(msgs);
    for (int k = 0; k < 3; ++k) m[rng.below(m.size())] ^= static_cast<std::uint8_t>(1 + rng.below(255));
    auto d = decode(m);
    if (!d.ok()) continue;
    ++accepted;
    Peer target(9);
    for (const auto& ok : msgs) target.receive(ok);
    target.g.merge(*d);
    auto v = target.g.check_invariants();
    ASSERT_TRUE(v.empty()) << "seed " << base << " iteration " << i << ": " << v.front();
  }
  EXPECT_GT(accepted, 0);
}

TEST(CodecTest, SteadyWritesCostFewBytes) {
  // The benchmark workload in miniature: overwrites of double registers, 100 per transaction.
  Peer a(1);
  std::vector<NodeId> ids;
  std::vector<Symbol> names;
  for (int k = 0; k < 10; ++k) names.emplace_back("a" + std::to_string(k));
  {
    auto tx = a.g.begin();
    for (int i = 0; i < 1000; ++i) {
      std::vector<std::pair<Symbol, Value>> init;
      for (Symbol s : names) init.emplace_back(s, Value(0.0));
      ids.push_back(*tx.create_node("o", "n" + std::to_string(i), init));
    }
    ASSERT_TRUE(tx.commit().ok());
  }
  Rng rng(1);
  for (int t = 0; t < 300; ++t) {
    auto tx = a.g.begin();
    for (int i = 0; i < 100; ++i) ASSERT_TRUE(tx.set(ids[rng.below(1000)], names[rng.below(10)], Value(rng.uniform())).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  std::size_t bytes = 0;
  for (std::size_t i = 201; i < a.outbox.size(); ++i) bytes += a.outbox[i].size();
  double per_write = static_cast<double>(bytes) / (100.0 * (a.outbox.size() - 201));
  EXPECT_LT(per_write, 16.0);
}

}  // namespace
}  // namespace quiver::graph

namespace quiver::graph {
namespace {

// A delta of replica 3 creating one node whose id is the dot (3, counter).
GraphDelta node_at(std::uint64_t counter) {
  GraphDelta d;
  d.kind = GraphDelta::Kind::kDelta;
  d.origin = ReplicaId{3, 1};
  d.context.add_range(d.origin, counter, counter);
  GraphDelta::NodeOp op;
  op.id = NodeId{Dot{d.origin, counter}};
  op.has_header = true;
  op.type = Symbol("thing");
  op.name = "far" + std::to_string(counter % 1000);
  d.nodes.push_back(op);
  return d;
}

TEST(CodecTest, CountersBeyondTheLimitAreRefused) {
  for (std::uint64_t c : {crdt::kMaxCounter, crdt::kMaxCounter + 1, std::uint64_t{UINT64_MAX}}) {
    auto r = decode(encode(node_at(c)));
    if (c <= crdt::kMaxCounter) {
      EXPECT_TRUE(r.ok()) << r.error().to_string();
    } else {
      ASSERT_FALSE(r.ok()) << "counter " << c << " accepted";
      EXPECT_NE(r.error().message.find("counter"), std::string::npos) << r.error().message;
    }
  }
}

// A peer that publishes a counter near the limit cannot exhaust this replica's counter space:
// its clock follows others only up to crdt::kClockCeiling, and every later delta still decodes.
TEST(CodecTest, ARemoteCounterNearTheLimitDoesNotExhaustOurs) {
  testing::Peer b(2);
  b.g.merge(*decode(encode(node_at(crdt::kMaxCounter - 1))));
  for (int i = 0; i < 100; ++i) {
    auto tx = b.g.begin();
    ASSERT_TRUE(tx.create_node("thing", "n" + std::to_string(i)).ok());
    auto c = tx.commit();
    ASSERT_TRUE(c.ok()) << c.error().to_string();
    EXPECT_LE(c->last_counter, crdt::kClockCeiling + 1000);
  }
  testing::Peer c(4);
  c.receive_all(b);
  EXPECT_EQ(c.g.node_count(), 100u) << "every delta decoded";
}

}  // namespace
}  // namespace quiver::graph
