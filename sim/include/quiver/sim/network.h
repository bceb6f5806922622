#pragma once
/// @file
/// The simulated world's clock and network, shared by every simulation: one event queue in
/// virtual time, and a network of nodes that exchange the samples DDS would ship (their CDR
/// bytes, agents/transport/wire/cdr_sample.h), one message each, with
/// per-link loss, duplication, delay and reordering, partitions (nodes in different groups do not
/// hear each other) and nodes that are down. Deterministic: every draw comes from the one Rng it
/// is given, and events at equal times run in the order they were scheduled.

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <queue>
#include <span>
#include <vector>

#include "quiver/agents/replica/replication/transport.h"
#include "quiver/agents/transport/wire/cdr_sample.h"
#include "quiver/base/rng.h"

namespace quiver::sim {

struct FaultConfig {
  /// Probability a sample's packet is lost on a link: a heartbeat (summary) is then lost, a
  /// sample of a reliable topic is sent again and arrives repair_min..max_ns late (as RTPS does).
  double loss = 0.0;
  double dup = 0.0;                  ///< probability a sample is delivered twice
  bool reorder = false;              ///< samples on a link may overtake each other
  bool partitions = false;           ///< split the agents into groups for a while, then heal
  bool crashes = false;              ///< kill agents (state lost) and restart them later
  std::int64_t delay_min_ns = 100'000;
  std::int64_t delay_max_ns = 2'000'000;
  std::int64_t reorder_jitter_ns = 30'000'000;
  std::int64_t repair_min_ns = 10'000'000;   ///< a reliable sample's retransmission: extra delay
  std::int64_t repair_max_ns = 100'000'000;
};

struct NetworkStats {
  std::uint64_t messages = 0;  ///< samples handed to the network, per destination
  std::uint64_t bytes = 0;     ///< their CDR bytes (what DDS would carry as sample payloads)
  std::uint64_t dropped = 0;        ///< packets lost: to loss, to a partition or to a host down
  std::uint64_t retransmitted = 0;  ///< of those, reliable samples sent again (they arrive late)
  std::uint64_t duplicated = 0;
  /// Peers introduced by discovery (discover()): what DDS discovery (SPDP) tells, counted apart
  /// from Quiver's messages and bytes, as Cyclone's own traffic is over DDS.
  std::uint64_t introductions = 0;
  /// messages and bytes by topic (agents::DdsTopic order: summary, delta, pull, state, bye)
  std::array<std::uint64_t, agents::kDdsTopicCount> topic_messages{}, topic_bytes{};
  /// bytes sent by nodes of a segment other than 0 (VirtualNetwork::set_segment), by segment
  std::vector<std::uint64_t> segment_bytes;
};

class VirtualNetwork {
 public:
  using Receiver = std::function<void(const agents::CdrSample& sample, std::int64_t now)>;

  VirtualNetwork(int nodes, Rng rng, FaultConfig faults);
  ~VirtualNetwork();
  VirtualNetwork(const VirtualNetwork&) = delete;
  VirtualNetwork& operator=(const VirtualNetwork&) = delete;

  std::int64_t now() const { return now_; }
  /// Runs `fn` at virtual time `t` (now if earlier).
  void at(std::int64_t t, std::function<void()> fn);
  /// Runs every event up to `t_end`; then now() is at least `t_end`.
  void run_until(std::int64_t t_end);
  /// Called after every event (e.g. to check an invariant continuously).
  void after_each_event(std::function<void()> fn) { after_event_ = std::move(fn); }

  /// Where samples for `node` go (decoded for the node's replicator), while it is up.
  void set_receiver(int node, Receiver r) { nodes_[node].receiver = std::move(r); }
  /// The replica id samples addressed to `node` carry (unicast), while it is up.
  void set_address(int node, const agents::PeerId& id) { nodes_[node].address = id; }
  /// Discovery, as DDS's participant discovery does it: `node` announces `card` (its replica id,
  /// name and role), and `introduce` is how it learns of the others. It is introduced at once to
  /// every node up in its group that announced itself, and they to it.
  using Introducer = std::function<void(const agents::PeerCard& card)>;
  void discover(int node, agents::PeerCard card, Introducer introduce);
  /// A transport for `node`: each sample it sends is serialized once and carried to the others.
  agents::Transport& endpoint(int node);

  /// A node that is down neither sends nor receives (samples in flight to it are lost).
  void set_up(int node, bool up) { nodes_[node].up = up; }
  bool up(int node) const { return nodes_[node].up; }
  /// Nodes hear each other only within one group (a sample sent across groups, or to a node whose
  /// group changed while it was in flight, is lost).
  void set_group(int node, int group) { nodes_[node].group = group; }
  int group(int node) const { return nodes_[node].group; }
  void heal() {
    for (auto& n : nodes_) n.group = 0;
  }
  /// Separate networks (a robot team: each robot's own, and the team's): a node hears only nodes
  /// of its segment (0 unless set); broadcasts and discovery stay within it.
  void set_segment(int node, int segment) { nodes_[node].segment = segment; }
  int segment(int node) const { return nodes_[node].segment; }
  /// The link faults of what nodes of `segment` send (instead of faults()): e.g. a slower, lossier
  /// team network.
  void set_segment_faults(int segment, const FaultConfig& f);
  FaultConfig* segment_faults(int segment);
  FaultConfig& faults() { return faults_; }
  const NetworkStats& stats() const { return stats_; }
  int size() const { return static_cast<int>(nodes_.size()); }
  /// The node a replica id addresses (up), or -1.
  int index_of(const agents::PeerId& id) const;

  /// Hands a serialized sample from `from` to `to` (-1: every other node).
  void transmit(int from, int to, std::shared_ptr<const agents::CdrSample> sample);

 private:
  struct Event {
    std::int64_t t = 0;
    std::uint64_t seq = 0;
    int node = -1;   // a delivery to this node, or -1: a call
    int group = 0;   // the sender's group when it sent
    std::shared_ptr<const agents::CdrSample> sample;
    std::function<void()> fn;
    bool operator>(const Event& o) const { return t != o.t ? t > o.t : seq > o.seq; }
  };
  struct Endpoint;
  struct Node {
    bool up = false;  // until the simulation starts it
    int group = 0;
    int segment = 0;
    agents::PeerId address;
    agents::PeerCard card;
    Introducer introduce;
    Receiver receiver;
    std::unique_ptr<Endpoint> endpoint;
  };
  void push(Event e);

  Rng rng_;
  FaultConfig faults_;
  std::vector<std::pair<int, FaultConfig>> segment_faults_;
  std::vector<Node> nodes_;
  std::priority_queue<Event, std::vector<Event>, std::greater<Event>> queue_;
  std::uint64_t next_seq_ = 0;
  std::int64_t now_ = 0;
  std::vector<std::int64_t> last_delivery_;  // FIFO links: per (from, to)
  NetworkStats stats_;
  std::function<void()> after_event_;
};

}  // namespace quiver::sim
