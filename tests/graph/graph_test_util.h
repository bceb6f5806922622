#pragma once
// A replica with an outbox of encoded deltas, for tests that ship deltas by hand.

#include <memory>
#include <string>
#include <vector>

#include "quiver/graph/codec.h"
#include "quiver/graph/graph.h"

namespace quiver::graph::testing {

struct Peer {
  explicit Peer(std::uint64_t agent, std::uint64_t incarnation = 1, GraphOptions opts = {})
      : g(ReplicaId{agent, incarnation}, opts) {
    g.set_delta_sink([this](const GraphDelta& d) { outbox.push_back(encode(d)); });
  }
  Graph g;
  std::vector<std::vector<std::uint8_t>> outbox;

  /// Decodes and merges every message of `from`'s outbox (kept there).
  void receive_all(const Peer& from) {
    for (const auto& m : from.outbox) receive(m);
  }
  void receive(const std::vector<std::uint8_t>& bytes) {
    auto d = decode(bytes);
    ASSERT_TRUE(d.ok()) << d.error().to_string();
    g.merge(*d);
  }
  /// Full-state transfer through the codec.
  void receive_state(const Peer& from) { receive(encode(from.g.state())); }
  void receive_diff(const Peer& from) { receive(encode(from.g.state_diff(g.context()))); }

  NodeId add(const std::string& type, const std::string& name) {
    auto tx = g.begin();
    auto id = tx.create_node(type, name);
    EXPECT_TRUE(id.ok()) << id.error().to_string();
    auto c = tx.commit();
    EXPECT_TRUE(c.ok());
    return *id;
  }
};

}  // namespace quiver::graph::testing
