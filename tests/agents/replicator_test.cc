#include "quiver/agents/replicator.h"

#include <gtest/gtest.h>

#include <deque>
#include <map>

#include "quiver/agents/frame_codec.h"
#include "quiver/graph/codec.h"

namespace quiver::agents {
namespace {

using graph::Graph;
using graph::ReplicaId;
using graph::Symbol;
using graph::Value;

// A hand-driven network: frames wait in a queue until the test delivers (or drops) them.
struct Net;
struct Port : Transport {
  Net* net;
  int index;
  void send(const Envelope& e) override;
};
struct Node {
  std::unique_ptr<Graph> g;
  std::unique_ptr<Port> port;
  std::unique_ptr<Replicator> rep;
  std::vector<std::pair<Membership, PeerInfo>> membership;
  std::vector<Error> errors;
};
struct Frame {
  int from, to;
  std::vector<std::uint8_t> bytes;
};
struct Net {
  std::vector<Node> nodes;
  std::deque<Frame> inflight;
  std::int64_t now = 0;
  std::function<bool(const Frame&)> drop;  // return true to lose a frame

  int add(std::uint64_t agent, ReplicatorOptions opt = {}) {
    Node n;
    n.g = std::make_unique<Graph>(ReplicaId{agent, 1});
    n.port = std::make_unique<Port>();
    n.port->net = this;
    n.port->index = static_cast<int>(nodes.size());
    opt.name = "agent" + std::to_string(agent);
    n.rep = std::make_unique<Replicator>(*n.g, *n.port, opt);
    nodes.push_back(std::move(n));
    Node& ref = nodes.back();
    int i = static_cast<int>(nodes.size()) - 1;
    ref.rep->on_membership([this, i](Membership m, const PeerInfo& p) { nodes[i].membership.emplace_back(m, p); });
    ref.rep->on_error([this, i](const Error& e) { nodes[i].errors.push_back(e); });
    ref.rep->start(now);
    return i;
  }
  int index_of(const PeerId& id) {
    for (std::size_t i = 0; i < nodes.size(); ++i)
      if (nodes[i].g && nodes[i].g->replica() == id) return static_cast<int>(i);
    return -1;
  }
  // Delivers everything in flight (and whatever that triggers), in order.
  void pump(int max = 100000) {
    while (!inflight.empty() && max-- > 0) {
      Frame f = std::move(inflight.front());
      inflight.pop_front();
      if (drop && drop(f)) continue;
      if (nodes[f.to].rep) nodes[f.to].rep->on_frame(f.bytes, now);
    }
  }
  void advance(std::int64_t ns, int ticks = 10) {
    for (int k = 0; k < ticks; ++k) {
      now += ns / ticks;
      for (auto& n : nodes)
        if (n.rep) n.rep->tick(now);
      pump();
    }
  }
};
void Port::send(const Envelope& e) {
  std::vector<std::uint8_t> f = encode_frame(e);
  if (e.to.is_null()) {
    for (std::size_t i = 0; i < net->nodes.size(); ++i)
      if (static_cast<int>(i) != index) net->inflight.push_back(Frame{index, static_cast<int>(i), f});
    return;
  }
  int d = net->index_of(e.to);
  if (d >= 0) net->inflight.push_back(Frame{index, d, f});
}

graph::NodeId add_node(Graph& g, const std::string& name) {
  auto tx = g.begin();
  auto id = tx.create_node("thing", name);
  EXPECT_TRUE(id.ok());
  EXPECT_TRUE(tx.commit().ok());
  return *id;
}

TEST(ReplicatorTest, DeltasReachEveryPeer) {
  Net net;
  int a = net.add(1), b = net.add(2), c = net.add(3);
  net.pump();
  add_node(*net.nodes[a].g, "x");
  add_node(*net.nodes[b].g, "y");
  net.pump();
  for (int i : {a, b, c}) {
    EXPECT_EQ(net.nodes[i].g->node_count(), 2u);
    EXPECT_EQ(net.nodes[i].g->digest(), net.nodes[a].g->digest());
  }
  EXPECT_EQ(net.nodes[c].rep->stats().deltas_applied, 2u);
}

TEST(ReplicatorTest, DuplicatesAreIgnored) {
  Net net;
  int a = net.add(1), b = net.add(2);
  net.pump();
  add_node(*net.nodes[a].g, "x");
  auto copy = net.inflight;
  net.pump();
  net.inflight = copy;
  net.pump();
  EXPECT_EQ(net.nodes[b].rep->stats().deltas_applied, 1u);
  EXPECT_EQ(net.nodes[b].rep->stats().deltas_duplicate, 1u);
}

TEST(ReplicatorTest, ALostDeltaIsPulledBack) {
  Net net;
  ReplicatorOptions opt;
  int a = net.add(1, opt), b = net.add(2, opt);
  net.pump();
  // Lose the first delta only.
  bool lost = false;
  net.drop = [&](const Frame& f) {
    if (!lost && f.from == a && f.to == b && f.bytes.size() > 40) return lost = true;
    return false;
  };
  add_node(*net.nodes[a].g, "x");
  add_node(*net.nodes[a].g, "y");
  net.pump();
  EXPECT_TRUE(lost);
  EXPECT_EQ(net.nodes[b].g->node_count(), 1u) << "only the second delta arrived";
  net.advance(500'000'000);
  EXPECT_EQ(net.nodes[b].g->node_count(), 2u);
  EXPECT_EQ(net.nodes[b].g->digest(), net.nodes[a].g->digest());
  EXPECT_GE(net.nodes[b].rep->stats().pulls_sent, 1u);
  EXPECT_GE(net.nodes[a].rep->stats().pulls_answered_with_deltas, 1u) << "served from the relay buffer";
}

TEST(ReplicatorTest, ARemovalOnlyDeltaLostIsDetectedBySequenceNumbers) {
  // A delete mints no dot: only the sequence number reveals that it went missing.
  Net net;
  int a = net.add(1), b = net.add(2);
  net.pump();
  auto x = add_node(*net.nodes[a].g, "x");
  net.pump();
  net.drop = [&](const Frame& f) { return f.from == a && f.to == b; };
  {
    auto tx = net.nodes[a].g->begin();
    ASSERT_TRUE(tx.delete_node(x).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  net.pump();
  net.drop = nullptr;
  EXPECT_TRUE(net.nodes[b].g->has_node(x));
  net.advance(500'000'000);
  EXPECT_FALSE(net.nodes[b].g->has_node(x));
}

TEST(ReplicatorTest, ALateJoinerGetsTheStateInChunksFromAnyPeer) {
  ReplicatorOptions opt;
  opt.chunk_bytes = 1024;
  opt.buffer_bytes = 4096;  // the early deltas are evicted: only a state transfer can help
  Net net;
  int a = net.add(1, opt), b = net.add(2, opt);
  net.pump();
  for (int i = 0; i < 200; ++i) {
    auto tx = net.nodes[a].g->begin();
    auto id = tx.create_node("thing", "n" + std::to_string(i), {{Symbol("payload"), Value(std::string(40, 'x'))}});
    ASSERT_TRUE(id.ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  net.advance(200'000'000);
  ASSERT_EQ(net.nodes[b].g->node_count(), 200u);
  // a goes silent; the newcomer must get everything from b.
  net.drop = [&](const Frame& f) { return f.from == a || f.to == a; };
  int c = net.add(3, opt);
  net.advance(1'000'000'000, 40);
  EXPECT_EQ(net.nodes[c].g->node_count(), 200u);
  EXPECT_EQ(net.nodes[c].g->digest(), net.nodes[b].g->digest());
  EXPECT_GE(net.nodes[b].rep->stats().pulls_answered_with_state, 1u);
  EXPECT_GE(net.nodes[c].rep->stats().states_applied, 1u);
  EXPECT_TRUE(net.nodes[c].rep->synced());
}

TEST(ReplicatorTest, LostStateChunksAreRetried) {
  ReplicatorOptions opt;
  opt.chunk_bytes = 1024;
  opt.max_frame_bytes = 1200;  // one chunk per frame
  opt.buffer_bytes = 1024;
  Net net;
  int a = net.add(1, opt);
  for (int i = 0; i < 100; ++i) {
    auto tx = net.nodes[a].g->begin();
    ASSERT_TRUE(tx.create_node("thing", "n" + std::to_string(i), {{Symbol("p"), Value(std::string(60, 'y'))}}).ok());
    ASSERT_TRUE(tx.commit().ok());
  }
  int b = net.add(2, opt);
  int chunks_dropped = 0;
  net.drop = [&](const Frame& f) {
    // Lose three state chunks on their way from a to b.
    if (f.from == a && f.to == b && f.bytes.size() > 900 && chunks_dropped < 3) {
      ++chunks_dropped;
      return true;
    }
    return false;
  };
  net.advance(3'000'000'000, 60);
  EXPECT_EQ(chunks_dropped, 3);
  EXPECT_EQ(net.nodes[b].g->node_count(), 100u);
  EXPECT_EQ(net.nodes[b].g->digest(), net.nodes[a].g->digest());
  EXPECT_GE(net.nodes[b].rep->stats().pulls_timed_out, 1u) << "the first transfer stalled";
  EXPECT_GE(net.nodes[b].rep->stats().states_applied, 1u);
}

TEST(ReplicatorTest, MembershipJoinLeaseAndGoodbye) {
  ReplicatorOptions opt;
  opt.lease_ns = 300'000'000;
  Net net;
  int a = net.add(1, opt), b = net.add(2, opt), c = net.add(3, opt);
  net.advance(100'000'000);
  EXPECT_EQ(net.nodes[a].rep->live_peer_count(), 2u);
  // c crashes silently: a notices when the lease expires.
  net.nodes[c].rep.reset();
  net.nodes[c].g.reset();
  net.advance(600'000'000, 20);
  EXPECT_EQ(net.nodes[a].rep->live_peer_count(), 1u);
  ASSERT_FALSE(net.nodes[a].membership.empty());
  EXPECT_EQ(net.nodes[a].membership.back().first, Membership::kLeft);
  EXPECT_EQ(net.nodes[a].membership.back().second.name, "agent3");
  // b leaves cleanly: a knows at once.
  net.nodes[b].rep->leave();
  net.pump();
  EXPECT_EQ(net.nodes[a].rep->live_peer_count(), 0u);
}

TEST(ReplicatorTest, MalformedFramesAreRejectedAndChangeNothing) {
  Net net;
  int a = net.add(1);
  add_node(*net.nodes[a].g, "x");
  auto before = net.nodes[a].g->digest();
  std::vector<std::uint8_t> junk = {'Q', 'R', 1, 0xff, 0xff};
  net.nodes[a].rep->on_frame(junk, 0);
  std::vector<std::uint8_t> future = {'Q', 'R', 9};
  net.nodes[a].rep->on_frame(future, 0);
  ASSERT_EQ(net.nodes[a].errors.size(), 2u);
  EXPECT_EQ(net.nodes[a].errors[0].code, ErrorCode::kTruncated);
  EXPECT_NE(net.nodes[a].errors[0].message.find("sender"), std::string::npos) << net.nodes[a].errors[0].message;
  EXPECT_EQ(net.nodes[a].errors[1].code, ErrorCode::kUnsupportedVersion);
  EXPECT_EQ(net.nodes[a].g->digest(), before);
  EXPECT_EQ(net.nodes[a].rep->stats().rejected_frames, 2u);
}

TEST(ReplicatorTest, ARogueDeltaWithCorruptPayloadIsRejected) {
  Net net;
  int a = net.add(1), b = net.add(2);
  net.pump();
  add_node(*net.nodes[a].g, "x");
  ASSERT_FALSE(net.inflight.empty());
  // Corrupt the graph payload inside the frame (last bytes).
  Frame f = net.inflight.back();
  net.inflight.clear();
  f.bytes[f.bytes.size() - 3] = 0xff;
  f.bytes[f.bytes.size() - 2] = 0xff;
  f.bytes[f.bytes.size() - 1] = 0xff;
  auto before = net.nodes[b].g->digest();
  net.nodes[b].rep->on_frame(f.bytes, 0);
  EXPECT_EQ(net.nodes[b].g->digest(), before);
  ASSERT_EQ(net.nodes[b].errors.size(), 1u);
  EXPECT_NE(net.nodes[b].errors[0].message.find("delta"), std::string::npos) << net.nodes[b].errors[0].message;
  // The genuine delta is still accepted later (the rogue copy did not mark it as applied).
  net.advance(500'000'000);
  EXPECT_EQ(net.nodes[b].g->digest(), net.nodes[a].g->digest());
}

TEST(ReplicatorTest, CoalescedIntervalsCarrySeveralCommits) {
  ReplicatorOptions opt;
  opt.coalesce = true;
  Net net;
  int a = net.add(1, opt), b = net.add(2);
  net.pump();
  for (int i = 0; i < 10; ++i) add_node(*net.nodes[a].g, "n" + std::to_string(i));
  EXPECT_TRUE(net.inflight.empty()) << "held until flush";
  net.nodes[a].rep->flush();
  net.pump();
  EXPECT_EQ(net.nodes[b].g->node_count(), 10u);
  EXPECT_EQ(net.nodes[b].rep->stats().deltas_applied, 1u);
  EXPECT_EQ(net.nodes[b].rep->applied().contiguous(net.nodes[a].g->replica()), 10u);
}

}  // namespace
}  // namespace quiver::agents
