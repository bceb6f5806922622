// A simulated robot team's gateway: two replicas and a bridge on two network nodes.
#include "sim_gateway.h"

#include "quiver/agents/transport/wire/cdr_sample.h"

namespace quiver::sim {

bool SimGateway::boot(VirtualNetwork& net, const Place& at, const agents::ReplicatorOptions& base,
                      std::function<void(const std::string&, const Error&)> on_error) {
  const bool from_store = incarnation > 0 && stored[0] && stored[1];
  if (!from_store) ++incarnation;
  for (int side = 0; side < 2; ++side) {
    const std::string name = at.name + (side == 0 ? "" : ".team");
    graph[side] = std::make_unique<graph::Graph>(
        graph::ReplicaId{at.replica_base + static_cast<std::uint64_t>(side), incarnation});
    if (from_store) graph[side]->merge(*stored[side].state);
    agents::ReplicatorOptions opt = base;
    opt.name = name;
    opt.gateway = true;
    opt.robot = at.robot;
    replicator[side] = std::make_unique<agents::Replicator>(*graph[side], net.endpoint(at.node[side]), opt);
    replicator[side]->on_error([on_error, name](const Error& e) { on_error(name, e); });
    if (from_store) replicator[side]->restore(stored[side].applied);
    stored[side] = KeptReplica{};
    net.set_up(at.node[side], true);
    net.set_address(at.node[side], graph[side]->replica());
  }
  bridge = std::make_unique<agents::ReplicaBridge>(*replicator[0], *replicator[1]);
  up = true;
  for (int side = 0; side < 2; ++side) {
    agents::Replicator& rep = *replicator[side];
    rep.start(net.now());
    net.discover(at.node[side], {graph[side]->replica(), rep.options().name, false, true},
                 [this, side](const agents::PeerCard& c) {
                   if (up) replicator[side]->introduce(c);
                 });
    net.set_receiver(at.node[side], [this, side](const agents::CdrSample& sample, std::int64_t now) {
      auto decoded = agents::decode_cdr_sample(sample.topic, sample.bytes);
      if (decoded.ok()) replicator[side]->on_sample(*decoded, now);
      else replicator[side]->on_undecodable(decoded.error());
      bridge->pump(now);
    });
  }
  return from_store;
}

std::uint64_t SimGateway::crash(VirtualNetwork& net, const Place& at, bool keep) {
  std::uint64_t rejected = 0;
  if (!up) return rejected;
  up = false;
  bridge.reset();
  for (int side = 0; side < 2; ++side) {
    net.set_up(at.node[side], false);
    rejected += replicator[side]->stats().rejected;
    if (keep) stored[side] = KeptReplica::of(*graph[side], *replicator[side]);
    replicator[side].reset();
    graph[side].reset();
  }
  return rejected;
}

void SimGateway::tick(std::int64_t now) {
  if (!up) return;
  for (auto& rep : replicator) rep->tick(now);
  bridge->pump(now);
}

}  // namespace quiver::sim
