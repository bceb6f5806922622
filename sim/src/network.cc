// The simulated network: delays, losses, retransmits of reliable samples, partitions, hosts down.
#include "quiver/sim/network.h"

#include <algorithm>

#include "quiver/agents/transport/wire/cdr_sample.h"

namespace quiver::sim {

// Serializes every sample as Cyclone DDS does (the CDR of its IDL type): the simulated network
// carries, and counts, exactly the bytes DDS ships, and receivers decode them as DDS does.
struct VirtualNetwork::Endpoint : agents::Transport {
  VirtualNetwork* net;
  int index;
  Endpoint(VirtualNetwork* n, int i) : net(n), index(i) {}
  void send(const agents::Sample& s) override {
    const int d = s.to.is_null() ? -1 : net->index_of(s.to);
    if (d < 0 && !s.to.is_null()) return;  // nobody has that address: nothing to encode
    net->transmit(index, d, std::make_shared<const agents::CdrSample>(agents::encode_cdr_sample(s)));
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

void VirtualNetwork::set_segment_faults(int segment, const FaultConfig& f) {
  if (FaultConfig* have = segment_faults(segment)) *have = f;
  else segment_faults_.emplace_back(segment, f);
}

FaultConfig* VirtualNetwork::segment_faults(int segment) {
  for (auto& [s, f] : segment_faults_)
    if (s == segment) return &f;
  return nullptr;
}

void VirtualNetwork::transmit(int from, int to, std::shared_ptr<const agents::CdrSample> sample) {
  if (!nodes_[from].up) return;  // a node that is down sends nothing (a host that fail-stopped)
  const int segment = nodes_[from].segment;
  const FaultConfig* own = segment_faults(segment);
  const FaultConfig& link = own != nullptr ? *own : faults_;
  auto one = [&](int d) {
    if (nodes_[d].segment != segment) return;  // another network: it never sees the sample
    ++stats_.messages;
    stats_.bytes += sample->bytes.size();
    ++stats_.topic_messages[static_cast<std::size_t>(sample->topic)];
    stats_.topic_bytes[static_cast<std::size_t>(sample->topic)] += sample->bytes.size();
    if (segment > 0) {
      if (stats_.segment_bytes.size() <= static_cast<std::size_t>(segment)) stats_.segment_bytes.resize(segment + 1);
      stats_.segment_bytes[segment] += sample->bytes.size();
    }
    if (!nodes_[d].up || nodes_[d].group != nodes_[from].group) {
      ++stats_.dropped;
      return;
    }
    // Loss as over DDS (agents/transport/dds): heartbeats (summaries, KEEP_LAST 1) are lost for
    // good, and a newer one follows; every other topic is RELIABLE, and the lost packet of a
    // reliable sample is sent again (RTPS): it arrives late, and the samples after it wait for it
    // on a FIFO link. A partition or a host down at its arrival still loses it.
    std::int64_t repair = 0;
    if (rng_.chance(link.loss)) {
      ++stats_.dropped;
      if (sample->topic == agents::DdsTopic::kSummary) return;
      ++stats_.retransmitted;
      repair = link.repair_min_ns +
               static_cast<std::int64_t>(rng_.below(static_cast<std::uint64_t>(link.repair_max_ns - link.repair_min_ns + 1)));
    }
    int copies = rng_.chance(link.dup) ? 2 : 1;
    stats_.duplicated += copies - 1;
    for (int c = 0; c < copies; ++c) {
      std::int64_t delay = link.delay_min_ns +
                           static_cast<std::int64_t>(rng_.below(link.delay_max_ns - link.delay_min_ns + 1));
      if (link.reorder) delay += static_cast<std::int64_t>(rng_.below(link.reorder_jitter_ns));
      std::int64_t t = now_ + delay + repair;
      std::int64_t& last = last_delivery_[static_cast<std::size_t>(from) * nodes_.size() + d];
      if (!link.reorder) t = std::max(t, last + 1);  // FIFO link
      last = std::max(last, t);
      Event e;
      e.t = t;
      e.node = d;
      e.group = nodes_[from].group;
      e.sample = sample;
      push(std::move(e));
    }
  };
  if (to >= 0) one(to);
  else
    for (int d = 0; d < size(); ++d)
      if (d != from) one(d);
}

void VirtualNetwork::discover(int node, agents::PeerCard card, Introducer introduce) {
  Node& n = nodes_[node];
  n.card = std::move(card);
  n.introduce = std::move(introduce);
  if (!n.up || !n.introduce) return;
  for (int d = 0; d < size(); ++d) {
    Node& o = nodes_[d];
    if (d == node || !o.up || o.group != n.group || o.segment != n.segment || !o.introduce) continue;
    o.introduce(n.card);
    n.introduce(o.card);
    stats_.introductions += 2;
  }
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
      // A sample sent across a partition that formed meanwhile, or to a node now down, is lost.
      if (n.up && n.group == e.group && n.receiver) n.receiver(*e.sample, now_);
      else ++stats_.dropped;
    }
    if (after_event_) after_event_();
  }
  now_ = std::max(now_, t_end);
}

}  // namespace quiver::sim
