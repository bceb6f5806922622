#pragma once
// A hand-driven network of replicators for protocol tests: samples (their CDR bytes, exactly what
// DDS ships) wait in a queue until the test delivers them, drops them, or advances time.

#include <gtest/gtest.h>

#include <deque>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "quiver/agents/replica/replication/replicator.h"
#include "quiver/agents/transport/wire/cdr_sample.h"

namespace quiver::agents {

using graph::Graph;
using graph::ReplicaId;

struct Net;
struct Port : Transport {
  Net* net;
  int index;
  void send(const Sample& s) override;
};
struct Node {
  std::unique_ptr<Graph> g;
  std::unique_ptr<Port> port;
  std::unique_ptr<Replicator> rep;
  std::vector<std::pair<Membership, PeerInfo>> membership;
  std::vector<Error> errors;
};
struct Packet {
  int from, to;
  CdrSample sample;
  /// The sample it carries, decoded as a receiver would.
  Sample decoded() const { return decode_cdr_sample(sample.topic, sample.bytes).value(); }
};
struct Net {
  std::vector<Node> nodes;
  std::deque<Packet> inflight;
  std::int64_t now = 0;
  std::function<bool(const Packet&)> drop;  // return true to lose a packet
  // When set, what the receiving transport authenticated of the node that sent a packet
  // (Sample::sender), as DDS Security's participant GUIDs do.
  std::function<std::array<std::uint8_t, 16>(int from)> sender;

  int add(std::uint64_t agent, ReplicatorOptions opt = {}) {
    Node n;
    n.g = std::make_unique<Graph>(ReplicaId{agent, 1});
    n.port = std::make_unique<Port>();
    n.port->net = this;
    n.port->index = static_cast<int>(nodes.size());
    if (opt.name.empty()) opt.name = "agent" + std::to_string(agent);
    n.rep = std::make_unique<Replicator>(*n.g, *n.port, opt);
    nodes.push_back(std::move(n));
    Node& ref = nodes.back();
    int i = static_cast<int>(nodes.size()) - 1;
    ref.rep->on_membership([this, i](Membership m, const PeerInfo& p) { nodes[i].membership.emplace_back(m, p); });
    ref.rep->on_error([this, i](const Error& e) { nodes[i].errors.push_back(e); });
    ref.rep->start(now);
    return i;
  }
  // Node `i` restarts as a process restarted from its store does: the same replica id
  // (incarnation kept), its graph and (origin, seq) set as they were, everything else new.
  void restart(int i, ReplicatorOptions opt) {
    Node& n = nodes[i];
    auto g = std::make_unique<Graph>(n.g->replica());
    g->merge(n.g->state());
    const crdt::CausalContext applied = n.rep->applied();
    n.rep.reset();
    n.g = std::move(g);
    if (opt.name.empty()) opt.name = "agent" + std::to_string(n.g->replica().agent);
    n.rep = std::make_unique<Replicator>(*n.g, *n.port, opt);
    n.rep->restore(applied);
    n.rep->on_membership([this, i](Membership m, const PeerInfo& p) { nodes[i].membership.emplace_back(m, p); });
    n.rep->on_error([this, i](const Error& e) { nodes[i].errors.push_back(e); });
    n.rep->start(now);
  }
  int index_of(const PeerId& id) {
    for (std::size_t i = 0; i < nodes.size(); ++i)
      if (nodes[i].g && nodes[i].g->replica() == id) return static_cast<int>(i);
    return -1;
  }
  // Delivers everything in flight (and whatever that triggers), in order.
  void pump(int max = 100000) {
    while (!inflight.empty() && max-- > 0) {
      Packet f = std::move(inflight.front());
      inflight.pop_front();
      if (drop && drop(f)) continue;
      if (!nodes[f.to].rep) continue;
      if (!sender) {
        deliver_cdr_sample(*nodes[f.to].rep, f.sample.topic, f.sample.bytes, now);
        continue;
      }
      auto s = decode_cdr_sample(f.sample.topic, f.sample.bytes);
      if (!s.ok()) {
        nodes[f.to].rep->on_undecodable(s.error());
        continue;
      }
      s->sender = sender(f.from);
      nodes[f.to].rep->on_sample(*s, now);
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
// Commits one node of type "thing" named `name` on `g` (a local change to replicate).
inline graph::NodeId add_node(Graph& g, const std::string& name) {
  auto tx = g.begin();
  auto id = tx.create_node("thing", name);
  EXPECT_TRUE(id.ok());
  EXPECT_TRUE(tx.commit().ok());
  return *id;
}

inline void Port::send(const Sample& e) {
  CdrSample f = encode_cdr_sample(e);
  if (e.to.is_null()) {
    for (std::size_t i = 0; i < net->nodes.size(); ++i)
      if (static_cast<int>(i) != index) net->inflight.push_back(Packet{index, static_cast<int>(i), f});
    return;
  }
  int d = net->index_of(e.to);
  if (d >= 0) net->inflight.push_back(Packet{index, d, f});
}


}  // namespace quiver::agents
