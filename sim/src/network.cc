#include "quiver/sim/network.h"

#include <algorithm>

#include "quiver/agents/replica/replication/packet_codec.h"

namespace quiver::sim {

// Encodes every envelope into a real byte packet: the simulated network carries (and counts)
// exactly what a byte transport would, and receivers decode it.
struct VirtualNetwork::Endpoint : agents::Transport {
  VirtualNetwork* net;
  int index;
  Endpoint(VirtualNetwork* n, int i) : net(n), index(i) {}
  void send(const agents::Envelope& e) override {
    const int d = e.to.is_null() ? -1 : net->index_of(e.to);
    if (d < 0 && !e.to.is_null()) return;  // nobody has that address: nothing to encode
    net->transmit(index, d, std::make_shared<const std::vector<std::uint8_t>>(agents::encode_packet(e)));
  }
};

VirtualNetwork::VirtualNetwork(int nodes, Rng rng, FaultConfig faults)
    : rng_(rng), faults_(faults), nodes_(static_cast<std::size_t>(nodes)) {
  for (int i = 0; i < nodes; ++i) nodes_[i].endpoint = std::make_unique<Endpoint>(this, i);
  last_delivery_.assign(static_cast<std::size_t>(nodes) * nodes, 0);
}

VirtualNetwork::~VirtualNetwork() = default;

agents::Transport& VirtualNetwork::endpoint(int node) { return *nodes_[node].endpoint; }

void VirtualNetwork::push(Event e) {
  e.seq = next_seq_++;
  queue_.push(std::move(e));
}

void VirtualNetwork::at(std::int64_t t, std::function<void()> fn) {
  Event e;
  e.t = std::max(t, now_);
  e.fn = std::move(fn);
  push(std::move(e));
}

int VirtualNetwork::index_of(const agents::PeerId& id) const {
  for (int i = 0; i < size(); ++i)
    if (nodes_[i].up && nodes_[i].address == id) return i;
  return -1;
}

void VirtualNetwork::transmit(int from, int to, std::shared_ptr<const std::vector<std::uint8_t>> packet) {
  if (!nodes_[from].up) return;  // a node that is down sends nothing (a host that fail-stopped)
  auto one = [&](int d) {
    ++stats_.messages;
    stats_.bytes += packet->size();
    if (!nodes_[d].up || nodes_[d].group != nodes_[from].group || rng_.chance(faults_.loss)) {
      ++stats_.dropped;
      return;
    }
    int copies = rng_.chance(faults_.dup) ? 2 : 1;
    stats_.duplicated += copies - 1;
    for (int c = 0; c < copies; ++c) {
      std::int64_t delay = faults_.delay_min_ns +
                           static_cast<std::int64_t>(rng_.below(faults_.delay_max_ns - faults_.delay_min_ns + 1));
      if (faults_.reorder) delay += static_cast<std::int64_t>(rng_.below(faults_.reorder_jitter_ns));
      std::int64_t t = now_ + delay;
      std::int64_t& last = last_delivery_[static_cast<std::size_t>(from) * nodes_.size() + d];
      if (!faults_.reorder) t = std::max(t, last + 1);  // FIFO link
      last = std::max(last, t);
      Event e;
      e.t = t;
      e.node = d;
      e.group = nodes_[from].group;
      e.packet = packet;
      push(std::move(e));
    }
  };
  if (to >= 0) one(to);
  else
    for (int d = 0; d < size(); ++d)
      if (d != from) one(d);
}

void VirtualNetwork::run_until(std::int64_t t_end) {
  while (!queue_.empty() && queue_.top().t <= t_end) {
    Event e = queue_.top();
    queue_.pop();
    now_ = std::max(now_, e.t);
    if (e.node < 0) {
      e.fn();
    } else {
      Node& n = nodes_[e.node];
      // A packet sent across a partition that formed meanwhile, or to a node now down, is lost.
      if (n.up && n.group == e.group && n.receiver) n.receiver(*e.packet, now_);
      else ++stats_.dropped;
    }
    if (after_event_) after_event_();
  }
  now_ = std::max(now_, t_end);
}

}  // namespace quiver::sim
