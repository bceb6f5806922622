// A replica's whole per-change path allocates nothing in steady state: the commit, its delta
// encoded and buffered, the heartbeats and buffer trimming of the protocol, and on the other side
// the delta decoded, checked, buffered and merged, with a change batch for a subscriber on each.
// The transport's own work is not counted: it copies what it sends, as DDS and the simulator do,
// with counting paused. Allocations are counted at malloc (count_allocations.h).
// (Its own executable: it replaces malloc for the whole process.)

#include <gtest/gtest.h>

#include <memory>
#include <variant>
#include <vector>

#include "count_allocations.h"
#include "quiver/agents/replica/replication/replicator.h"
#include "quiver/graph/graph.h"

namespace quiver::agents {
namespace {

using test_alloc::CountAllocations;

/// Keeps what a replica sends for the test to deliver, each delta's payload copied (a transport
/// ships bytes: the receiver never holds the sender's buffer). Its own allocations are not counted.
struct CopyingWire : Transport {
  std::vector<Sample> out;
  CopyingWire() { out.reserve(256); }
  void send(const Sample& s) override {
    const bool counting = test_alloc::t_counting;
    test_alloc::t_counting = false;
    out.push_back(s);
    if (auto* d = std::get_if<DeltaMsg>(&out.back().message))
      d->payload = std::make_shared<const std::vector<std::uint8_t>>(*d->payload);
    test_alloc::t_counting = counting;
  }
};

struct Replica {
  explicit Replica(std::uint64_t agent, const char* name)
      : g(graph::ReplicaId{agent, 1}), r(g, wire, options(name)) {
    g.subscribe([this](const graph::ChangeBatch& b) { changes += b.nodes.size() + b.edges.size(); });
  }
  static ReplicatorOptions options(const char* name) {
    ReplicatorOptions o;
    o.name = name;
    return o;
  }
  graph::Graph g;
  CopyingWire wire;
  Replicator r;
  std::size_t changes = 0;
};

struct Pair {
  Replica a{1, "writer"}, b{2, "reader"};
  std::int64_t now = 1'000'000'000;
  std::vector<graph::NodeId> ids;

  Pair() {
    a.r.start(now);
    b.r.start(now);
    for (int i = 0; i < 20; ++i) step(100'000'000);  // they meet
    auto tx = a.g.begin();
    for (int i = 0; i < 8; ++i) {
      auto id = tx.create_node("part", "part" + std::to_string(i), {{graph::Symbol("x"), graph::Value(0.0)}});
      EXPECT_TRUE(id.ok());
      ids.push_back(*id);
    }
    EXPECT_TRUE(tx.commit().ok());
    step(10'000'000);
  }
  /// Time passes; both tick, and what they sent is delivered (a few rounds: answers to answers).
  void step(std::int64_t ns) {
    now += ns;
    a.r.tick(now);
    b.r.tick(now);
    for (int round = 0; round < 3; ++round) {
      for (const Sample& s : a.wire.out) b.r.on_sample(s, now);
      a.wire.out.clear();
      for (const Sample& s : b.wire.out) a.r.on_sample(s, now);
      b.wire.out.clear();
    }
  }
  /// One change committed on a, flushed, and 10 ms of protocol time (100 changes a second).
  void change(int i) {
    auto tx = a.g.begin();
    ASSERT_TRUE(tx.set(ids[static_cast<std::size_t>(i) % ids.size()], graph::Symbol("x"), graph::Value(1.0 + i)).ok());
    ASSERT_TRUE(tx.commit().ok());
    a.r.flush();
    step(10'000'000);
  }
};

TEST(ReplicatorAllocationTest, ACommitItsDeltaAndItsMergeAllocateNothingInSteadyState) {
  Pair p;
  // Steady state: the relay buffers have reached the size at which they drop as many deltas as
  // they take (the writer's once the reader acknowledged them, the reader's after relay_retain_ns).
  constexpr int kWarm = 2000, kCounted = 2000;
  for (int i = 0; i < kWarm; ++i) p.change(i);
  const std::size_t seen = p.b.changes;
  {
    CountAllocations counted;
    for (int i = kWarm; i < kWarm + kCounted; ++i) p.change(i);
    EXPECT_EQ(counted.count(), 0) << counted.count() << " allocations in " << kCounted
                                  << " changes (20 s of protocol time)";
  }
  EXPECT_EQ(p.b.changes - seen, static_cast<std::size_t>(kCounted)) << "every change reached the reader";
  EXPECT_EQ(p.a.g.digest(), p.b.g.digest());
  EXPECT_GT(p.a.r.stats().deltas_published, static_cast<std::uint64_t>(kWarm + kCounted));
}

// The counter sees what this path allocates: a change that makes a node allocates (its record,
// its name on both replicas), so the test above can fail.
TEST(ReplicatorAllocationTest, TheCounterSeesWhatTheReplicatorAllocates) {
  Pair p;
  CountAllocations counted;
  auto tx = p.a.g.begin();
  ASSERT_TRUE(tx.create_node("part", "a-part-made-while-counting").ok());
  ASSERT_TRUE(tx.commit().ok());
  p.a.r.flush();
  p.step(10'000'000);
  EXPECT_GT(counted.count(), 0);
}

}  // namespace
}  // namespace quiver::agents
