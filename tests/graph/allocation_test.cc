// The per-change path of a replica allocates nothing in steady state: a commit of one change
// (its transaction, the delta, its encoding, the change batch for a subscriber) and the other
// side's decode and merge (with its change batch), once a change like it has gone the same way.
// Every heap allocation goes through malloc, which this executable counts (count_allocations.h):
// a test fails naming how many allocations the changes took.
// (Its own executable: it replaces malloc for the whole process.)

#include <gtest/gtest.h>

#include <vector>

#include "count_allocations.h"
#include "quiver/graph/codec.h"
#include "quiver/graph/graph.h"

namespace quiver::graph {
namespace {

using quiver::test_alloc::CountAllocations;

/// Two replicas joined by hand: the writer's sink encodes into one reused buffer, the reader
/// decodes it into one reused delta and merges it; both have a subscriber, as agents do.
struct Pair {
  Graph writer{ReplicaId{1, 1}};
  Graph reader{ReplicaId{2, 1}};
  std::vector<std::uint8_t> wire;
  GraphDelta received;
  std::size_t writer_batches = 0, reader_batches = 0, reader_changes = 0;
  std::vector<NodeId> ids;

  Pair() {
    writer.set_delta_sink([this](const GraphDelta& d) {
      wire.clear();
      encode(d, wire);
    });
    writer.subscribe([this](const ChangeBatch&) { ++writer_batches; });
    reader.subscribe([this](const ChangeBatch& b) {
      ++reader_batches;
      reader_changes += b.nodes.size() + b.edges.size();
    });
    auto tx = writer.begin();
    for (int i = 0; i < 8; ++i) {
      auto id = tx.create_node("part", "part" + std::to_string(i), {{Symbol("x"), Value(0.0)}});
      EXPECT_TRUE(id.ok());
      ids.push_back(*id);
    }
    EXPECT_TRUE(tx.insert_edge(ids[0], ids[1], Symbol("near")).ok());
    for (int i = 2; i < 6; ++i) EXPECT_TRUE(tx.set_rt(ids[0], ids[i], Pose{}, 1).ok());
    EXPECT_TRUE(tx.commit().ok());
    ship();
  }
  void ship() {
    ASSERT_TRUE(decode(wire, received).ok());
    reader.merge(received);
  }
};

// Runs `change` (a commit on the writer) `n` times, each shipped to the reader.
template <class F>
void run(Pair& p, int n, F change) {
  for (int i = 0; i < n; ++i) {
    change(i);
    p.ship();
  }
}

constexpr int kWarm = 50, kCounted = 200;

TEST(AllocationTest, AnAttributeWriteAndItsMergeAllocateNothingOnceWarm) {
  Pair p;
  const Symbol x("x");
  auto write = [&](int i) {
    auto tx = p.writer.begin();
    ASSERT_TRUE(tx.set(p.ids[static_cast<std::size_t>(i) % p.ids.size()], x, Value(1.0 + i)).ok());
    ASSERT_TRUE(tx.commit().ok());
  };
  run(p, kWarm, write);
  const std::size_t changes = p.reader_changes;
  {
    CountAllocations counted;
    run(p, kCounted, write);
    EXPECT_EQ(counted.count(), 0) << counted.count() << " allocations in " << kCounted << " writes and merges";
  }
  EXPECT_EQ(p.reader_changes - changes, static_cast<std::size_t>(kCounted)) << "every write reached the reader";
  EXPECT_EQ(p.writer.digest(), p.reader.digest());
}

TEST(AllocationTest, AnRtMoveAndItsMergeAllocateNothingOnceWarm) {
  Pair p;
  std::int64_t stamp = 1;  // each move newer than the last: the child's current pose changes
  auto move = [&](int i) {
    Pose X;
    X.translation = {0.01 * i, 0.0, 0.5};
    auto tx = p.writer.begin();
    ASSERT_TRUE(tx.set_rt(p.ids[0], p.ids[2 + static_cast<std::size_t>(i) % 4], X, ++stamp).ok());
    ASSERT_TRUE(tx.commit().ok());
  };
  // Steady state: each of the four children's pose history has filled to its depth.
  run(p, 4 * static_cast<int>(kRtHistoryDepth) + kWarm, move);
  const std::size_t changes = p.reader_changes;
  {
    CountAllocations counted;
    run(p, kCounted, move);
    EXPECT_EQ(counted.count(), 0) << counted.count() << " allocations in " << kCounted << " moves and merges";
  }
  EXPECT_EQ(p.reader_changes - changes, static_cast<std::size_t>(kCounted));
  EXPECT_EQ(p.writer.digest(), p.reader.digest());
}

TEST(AllocationTest, AnEdgeAttributeWriteAndItsMergeAllocateNothingOnceWarm) {
  Pair p;
  const EdgeKey near{p.ids[0], p.ids[1], Symbol("near")};
  const Symbol d("distance");
  auto write = [&](int i) {
    auto tx = p.writer.begin();
    ASSERT_TRUE(tx.set_edge_attr(near, d, Value(0.5 * i)).ok());
    ASSERT_TRUE(tx.commit().ok());
  };
  run(p, kWarm, write);
  {
    CountAllocations counted;
    run(p, kCounted, write);
    EXPECT_EQ(counted.count(), 0) << counted.count() << " allocations in " << kCounted << " edge writes and merges";
  }
  EXPECT_EQ(p.writer.digest(), p.reader.digest());
}

// The counter sees what the path allocates: a change that makes a node does allocate (its
// record, its name), so the tests above can fail.
TEST(AllocationTest, TheCounterCountsWhatAChangeAllocates) {
  Pair p;
  CountAllocations counted;
  auto tx = p.writer.begin();
  ASSERT_TRUE(tx.create_node("part", "a-fresh-part-with-a-long-name").ok());
  ASSERT_TRUE(tx.commit().ok());
  p.ship();
  EXPECT_GT(counted.count(), 0);
}

}  // namespace
}  // namespace quiver::graph
