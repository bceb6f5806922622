// States in parts: encoded from a replica's records a part at a time (encode_state(),
// codec encode_parts()) and joined a part at a time (merge_state(), decode_parts(); state_parts.h).
//  - an encoded state holds what state_diff() holds: joined, it leaves a replica as the
//    encoding of state_diff() does, and its keep list is the same;
//  - under random churn, joining in parts leaves a replica exactly as decode() and merge() of the whole state
//    do (digest, context, invariants and the change events), into an empty replica and into one
//    that holds entries the sender removed, whatever the part size;
//  - a message that does not decode, a delta, or a part that admission refuses joins nothing;
//  - a forged state's removed node ids remove those nodes whichever part names them;
//  - admission sees every op of the state once, in parts of the size asked;
//  - merge observers see the state whole.

#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <sstream>

#include "graph_test_util.h"
#include "quiver/base/rng.h"
#include "quiver/graph/state_parts.h"
#include "quiver/sim/workload.h"
#include "test_seed.h"

namespace quiver::graph {
namespace {

using testing::Peer;

// Every change of every batch, as text: what events a join produced (a batch's changes as a
// set: their order within a batch follows the graph's hash tables, RT changes even the records'
// addresses).
struct EventLog {
  explicit EventLog(Graph& g) {
    g.subscribe([this](const ChangeBatch& b) {
      std::multiset<std::string> changes;
      for (const auto& n : b.nodes) {
        std::ostringstream o;
        o << "node " << n.id.to_string() << " " << static_cast<int>(n.kind) << " " << n.name << " attrs";
        for (Symbol s : n.attrs) o << " " << s.str();
        changes.insert(o.str());
      }
      for (const auto& e : b.edges)
        changes.insert("edge " + e.key.to_string() + " " + std::to_string(static_cast<int>(e.kind)));
      batches.push_back(changes);
    });
  }
  std::vector<std::multiset<std::string>> batches;
};

// Random churn over three replicas, every delta delivered to every other one.
std::vector<std::unique_ptr<Peer>> churn(Rng& rng, int steps) {
  std::vector<std::unique_ptr<Peer>> peers;
  for (int i = 0; i < 3; ++i) peers.push_back(std::make_unique<Peer>(200 + i));
  sim::Churn work;
  for (int s = 0; s < steps; ++s) {
    const int who = static_cast<int>(rng.below(3));
    const std::size_t before = peers[who]->outbox.size();
    work.step(peers[who]->g, rng, s * 1000);
    for (std::size_t i = before; i < peers[who]->outbox.size(); ++i)
      for (int to = 0; to < 3; ++to)
        if (to != who && rng.chance(0.8)) peers[to]->receive(peers[who]->outbox[i]);
  }
  return peers;
}

std::unique_ptr<Peer> copy_of(const Peer& p, std::uint64_t id) {
  auto c = std::make_unique<Peer>(id);
  c->receive_state(p);
  return c;
}

// What a state goes into: an empty replica (target 0, a joiner) or a copy of `holder` (target 1,
// which holds entries the sender removed and lacks some of its own).
std::unique_ptr<Peer> target_replica(int target, const Peer& holder, std::uint64_t id) {
  return target == 0 ? std::make_unique<Peer>(id) : copy_of(holder, id);
}

TEST(GraphStatePartsTest, PartsJoinAsTheWholeStateDoes) {
  const auto base = quiver::testing::base_seed("GraphStatePartsTest.PartsJoinAsTheWholeStateDoes", 4100);
  for (int s = 0; s < quiver::testing::seed_count(60); ++s) {
    const std::uint64_t seed = base + s;
    Rng rng(seed);
    auto peers = churn(rng, 60);
    ASSERT_FALSE(HasFailure()) << "seed " << seed;
    // Into an empty replica (a joiner) and into a copy of replica 1 (which holds entries replica
    // 0 removed, and lacks some of its own): replica 0's whole state, and its diff against the
    // copy.
    for (int target = 0; target < 2; ++target) {
      for (bool diff : {false, true}) {
        for (std::size_t part_ops : {std::size_t{1}, std::size_t{3}, std::size_t{256}}) {
          auto whole = target_replica(target, *peers[1], 300);
          auto parts = target_replica(target, *peers[1], 300);
          const auto bytes = encode(diff ? peers[0]->g.state_diff(whole->g.context()) : peers[0]->g.state());
          EventLog whole_events(whole->g), parts_events(parts->g);
          whole->receive(bytes);
          GraphDelta scratch;
          Status st = merge_state(parts->g, bytes, scratch, {}, {}, part_ops);
          const std::string where = "seed " + std::to_string(seed) + ", target " + std::to_string(target) +
                                    (diff ? ", diff" : ", state") + ", parts of " + std::to_string(part_ops);
          ASSERT_TRUE(st.ok()) << st.error().to_string() << ", " << where;
          ASSERT_EQ(parts->g.digest(), whole->g.digest()) << where;
          ASSERT_EQ(parts->g.context(), whole->g.context()) << where;
          ASSERT_EQ(parts->g.check_invariants(), std::vector<std::string>{}) << where;
          ASSERT_EQ(parts_events.batches, whole_events.batches) << where;
        }
      }
    }
    // And the state brings the joiner up to replica 0.
    Peer joiner(301);
    GraphDelta scratch;
    ASSERT_TRUE(merge_state(joiner.g, encode(peers[0]->g.state()), scratch, {}, {}, 2).ok());
    ASSERT_EQ(joiner.g.digest(), peers[0]->g.digest()) << "seed " << seed;
  }
}

TEST(GraphStatePartsTest, AnEncodedStateHoldsWhatStateDiffHolds) {
  const auto base = quiver::testing::base_seed("GraphStatePartsTest.AnEncodedStateHoldsWhatStateDiffHolds", 5200);
  for (int s = 0; s < quiver::testing::seed_count(60); ++s) {
    const std::uint64_t seed = base + s;
    Rng rng(seed);
    auto peers = churn(rng, 60);
    ASSERT_FALSE(HasFailure()) << "seed " << seed;
    for (int target = 0; target < 2; ++target) {
      for (std::size_t part_ops : {std::size_t{1}, std::size_t{4}, std::size_t{256}}) {
        auto by_diff = target_replica(target, *peers[1], 310);
        auto by_parts = target_replica(target, *peers[1], 310);
        const GraphDelta diff = peers[0]->g.state_diff(by_diff->g.context());
        std::vector<std::uint8_t> bytes;
        encode_state(peers[0]->g, by_parts->g.context(), bytes, part_ops);
        const std::string where =
            "seed " + std::to_string(seed) + ", target " + std::to_string(target) + ", parts of " + std::to_string(part_ops);
        auto decoded = decode(bytes);
        ASSERT_TRUE(decoded.ok()) << decoded.error().to_string() << ", " << where;
        EXPECT_EQ(decoded->kind, GraphDelta::Kind::kState) << where;
        EXPECT_EQ(decoded->nodes.size(), diff.nodes.size()) << where;
        EXPECT_EQ(decoded->edges.size(), diff.edges.size()) << where;
        EXPECT_EQ(decoded->values.size(), diff.values.size()) << where;
        EXPECT_EQ(decoded->context, diff.context) << where;
        auto sorted = [](std::vector<Dot> v) {
          std::sort(v.begin(), v.end());
          return v;
        };
        EXPECT_EQ(sorted(decoded->keep), sorted(diff.keep)) << where;
        EventLog diff_events(by_diff->g), parts_events(by_parts->g);
        by_diff->receive(encode(diff));
        by_parts->receive(bytes);
        ASSERT_EQ(by_parts->g.digest(), by_diff->g.digest()) << where;
        if (target == 0) ASSERT_EQ(by_parts->g.digest(), peers[0]->g.digest()) << where;
        ASSERT_EQ(parts_events.batches, diff_events.batches) << where;
      }
    }
  }
}

TEST(GraphStatePartsTest, AStateOfNoPartsIsAnEmptyState) {
  std::vector<std::uint8_t> bytes;
  encode_parts([](PartOps, const std::function<void(const GraphDelta&)>&) {}, bytes);
  auto d = decode(bytes);
  ASSERT_TRUE(d.ok()) << d.error().to_string();
  EXPECT_EQ(d->kind, GraphDelta::Kind::kState);
  EXPECT_TRUE(d->nodes.empty());
  EXPECT_TRUE(d->context.empty());
  // And an empty replica's state, encoded in parts, joins as nothing.
  Peer empty(311), into(312);
  bytes.clear();
  encode_state(empty.g, {}, bytes);
  GraphDelta scratch;
  ASSERT_TRUE(merge_state(into.g, bytes, scratch).ok());
  EXPECT_EQ(into.g.digest(), empty.g.digest());
}

// A world of `n` nodes with two attributes each and a chain of edges.
std::unique_ptr<Peer> world(int n) {
  auto p = std::make_unique<Peer>(400);
  auto tx = p->g.begin();
  NodeId prev;
  for (int i = 0; i < n; ++i) {
    auto id = tx.create_node("object", "o" + std::to_string(i), {{Symbol("x"), Value(double(i))}, {Symbol("y"), Value(i)}});
    EXPECT_TRUE(id.ok());
    if (i > 0) EXPECT_TRUE(tx.insert_edge(prev, *id, "next").ok());
    prev = *id;
  }
  EXPECT_TRUE(tx.commit().ok());
  return p;
}

TEST(GraphStatePartsTest, WhatDoesNotDecodeJoinsNothing) {
  auto from = world(40);
  const auto bytes = encode(from->g.state());
  Peer into(401);
  into.add("object", "mine");
  const Digest128 before = into.g.digest();
  GraphDelta scratch;
  // Cut short: the first parts decode, the end does not.
  std::vector<std::uint8_t> cut(bytes.begin(), bytes.end() - 1);
  Status s = merge_state(into.g, cut, scratch, {}, {}, 1);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().code, ErrorCode::kTruncated) << s.error().to_string();
  EXPECT_EQ(into.g.digest(), before);
  // Trailing bytes after the last op.
  std::vector<std::uint8_t> longer = bytes;
  longer.push_back(0);
  s = merge_state(into.g, longer, scratch, {}, {}, 1);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().message.find("trailing"), std::string::npos) << s.error().to_string();
  EXPECT_EQ(into.g.digest(), before);
  // A delta is not a state.
  ASSERT_FALSE(from->outbox.empty());
  s = merge_state(into.g, from->outbox.front(), scratch, {}, {}, 1);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().code, ErrorCode::kMalformed);
  EXPECT_NE(s.error().message.find("only a state"), std::string::npos) << s.error().to_string();
  EXPECT_EQ(into.g.digest(), before);
  // The whole message still joins.
  ASSERT_TRUE(merge_state(into.g, bytes, scratch, {}, {}, 1).ok());
  EXPECT_EQ(into.g.node_count(), 41u);
}

TEST(GraphStatePartsTest, AdmissionSeesEveryPartAndARefusalJoinsNothing) {
  auto from = world(40);
  const auto bytes = encode(from->g.state());
  Peer into(402);
  const Digest128 before = into.g.digest();
  GraphDelta scratch;
  std::size_t parts = 0, nodes = 0, edges = 0, largest = 0;
  auto count = [&](const GraphDelta& p) {
    ++parts;
    nodes += p.nodes.size();
    edges += p.edges.size();
    largest = std::max(largest, p.nodes.size() + p.edges.size());
    return Status{};
  };
  ASSERT_TRUE(merge_state(into.g, bytes, scratch, count, {}, 8).ok());
  EXPECT_EQ(nodes, 40u);
  EXPECT_EQ(edges, 39u);
  EXPECT_EQ(largest, 8u);
  EXPECT_EQ(parts, 10u);  // 79 ops in parts of 8
  EXPECT_EQ(into.g.digest(), from->g.digest());

  // A refusal of the last part: nothing joins, and the refusal comes back.
  Peer other(403);
  std::size_t seen = 0;
  auto refuse_last = [&](const GraphDelta& p) {
    seen += p.nodes.size() + p.edges.size();
    if (seen == 79) return Status(make_error(ErrorCode::kPermissionDenied, "the last part is refused"));
    return Status{};
  };
  Status s = merge_state(other.g, bytes, scratch, refuse_last, {}, 8);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().message, "the last part is refused");
  EXPECT_EQ(other.g.digest(), before);
  EXPECT_EQ(other.g.node_count(), 0u);
}

// A forged state whose first attribute op removes a dot that is a node's id: that node goes, as
// in a whole state's join, though the dot comes in the first of many parts.
TEST(GraphStatePartsTest, ARemovedNodeIdInAnEarlyPartRemovesTheNode) {
  auto from = world(20);
  GraphDelta st = from->g.state();
  ASSERT_FALSE(st.attrs.empty());
  ASSERT_TRUE(st.removed.empty());
  const NodeId victim = st.nodes.back().id;
  st.removed.push_back(victim.dot);
  st.attrs.front().removed = {0, 1};
  const auto bytes = encode(st);
  auto whole = copy_of(*from, 405);
  auto parts = copy_of(*from, 405);
  ASSERT_TRUE(parts->g.has_node(victim));
  whole->receive(bytes);
  GraphDelta scratch;
  ASSERT_TRUE(merge_state(parts->g, bytes, scratch, {}, {}, 1).ok());
  EXPECT_FALSE(whole->g.has_node(victim));
  EXPECT_FALSE(parts->g.has_node(victim));
  EXPECT_EQ(parts->g.digest(), whole->g.digest());
}

TEST(GraphStatePartsTest, MergeObserversSeeTheStateWhole) {
  auto from = world(30);
  Peer into(404);
  std::vector<std::size_t> seen;
  into.g.add_merge_observer([&](const Graph&, const GraphDelta& d) { seen.push_back(d.nodes.size()); });
  GraphDelta scratch;
  ASSERT_TRUE(merge_state(into.g, encode(from->g.state()), scratch, {}, {}, 4).ok());
  EXPECT_EQ(seen, std::vector<std::size_t>{30});
  EXPECT_EQ(into.g.digest(), from->g.digest());
}

TEST(GraphStatePartsTest, DecodePartsSplitsAsAsked) {
  auto from = world(25);
  const auto bytes = encode(from->g.state());
  auto whole = decode(bytes);
  ASSERT_TRUE(whole.ok());
  GraphDelta scratch;
  std::size_t nodes = 0, edges = 0, values = 0, calls = 0;
  Status s = decode_parts(bytes, scratch, 5, [&](const GraphDelta& p) {
    ++calls;
    EXPECT_LE(p.nodes.size() + p.edges.size(), 5u);
    EXPECT_EQ(p.context, whole->context);  // every part carries the message's context
    nodes += p.nodes.size();
    edges += p.edges.size();
    values += p.values.size();
    return Status{};
  });
  ASSERT_TRUE(s.ok()) << s.error().to_string();
  EXPECT_EQ(calls, 10u);  // 49 ops in parts of 5
  EXPECT_EQ(nodes, whole->nodes.size());
  EXPECT_EQ(edges, whole->edges.size());
  EXPECT_EQ(values, whole->values.size());
  EXPECT_EQ(scratch.keep, whole->keep);
  // A sink's error stops the decoding and comes back.
  calls = 0;
  s = decode_parts(bytes, scratch, 5, [&](const GraphDelta&) {
    return ++calls == 2 ? Status(make_error(ErrorCode::kInvalidArgument, "stop")) : Status{};
  });
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().message, "stop");
  EXPECT_EQ(calls, 2u);
}

}  // namespace
}  // namespace quiver::graph
