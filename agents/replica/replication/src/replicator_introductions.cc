// Replicator introductions (gossip): peers a transport's own discovery tells of (DDS's
// participant discovery, the simulator's network), and the hello of a replica that starts, sent
// to a few introduced peers instead of to everyone. docs/protocol.md, "Introductions by the
// transport" and "Joining".

#include "quiver/agents/replica/replication/replicator.h"

namespace quiver::agents::inline replica {

void Replicator::introduce(const PeerCard& card) {
  const PeerId& peer = card.id;
  if (!opt_.gossip || peer == self_ || peer.is_null()) return;
  introduced_ = true;
  Peer* p = add_peer(peer);
  if (p != nullptr && card.gateway && !seen(*p).gateway) {
    d(*p).gateway = true;  // its acknowledgements count only from its hold answers
    ask_again();
  }
  // Named only by a name that hashes to its id: nobody can name another agent.
  if (p == nullptr || p->announced || card.name.size() > opt_.limits.max_name_bytes || !remember_name(peer, card.name))
    return;
  d(*p).name = card.name;
  p->named = !card.name.empty();
  p->observer = card.observer;
  p->announced = true;
  // Discovery goes both ways (each participant's card reaches the others): the peer has our
  // name from ours, and our beats to it need not carry it.
  p->told_name = true;
  if (membership_cb_ && p->alive) membership_cb_(Membership::kJoined, info_of(*p));
}

Replicator::Peer* Replicator::add_peer(const PeerId& peer) {
  if (auto it = peers_.find(peer); it != peers_.end()) return &it->second;
  if (peers_.size() >= opt_.max_peers) return nullptr;
  Peer& p = peers_[peer];
  p.id = peer;
  p.alive = true;
  d(p).heard_ns = now_;
  retire_older_incarnations(peer);
  return &p;
}

// A replica whose transport introduces peers (hello_answers()) says hello to a few live ones, each
// of which answers with its set's hash and count; one alone, or without introductions, says it
// to everyone.
void Replicator::say_hello() {
  std::vector<PeerId> live;
  if (hello_answers() > 0)
    for (const auto& [id, p] : peers_)
      if (p.alive && !p.said_bye) live.push_back(id);
  if (live.empty()) return send_beat(Beat::kHello, PeerId{});
  for (int k = 0; k < hello_answers() && !live.empty(); ++k) {
    const std::size_t i = rng_.below(live.size());
    send_beat(Beat::kHello, live[i]);
    live[i] = live.back();
    live.pop_back();
  }
}

}  // namespace quiver::agents
