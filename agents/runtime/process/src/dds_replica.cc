// A replica on DDS: one graph replica, its replicator, its store if any and the Cyclone DDS transport, driven by
// the agent engine on the thread that spins it.
#include "quiver/agents/runtime/process/dds_replica.h"

#include <algorithm>
#include <chrono>
#include <random>

#include "quiver/base/hash.h"

namespace quiver::agents::inline runtime {

std::uint64_t fresh_incarnation() {
  auto us = std::chrono::duration_cast<std::chrono::microseconds>(
                std::chrono::system_clock::now().time_since_epoch())
                .count();
  std::random_device rd;
  return (static_cast<std::uint64_t>(us) << 12) | (rd() & 0xfff);
}

std::int64_t monotonic_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

Result<std::unique_ptr<DdsReplica>> DdsReplica::create(DdsReplicaOptions options) {
  if (options.name.empty()) return make_error(ErrorCode::kInvalidArgument, "DdsReplica::create(): the name is empty");
  std::unique_ptr<DdsReplica> a(new DdsReplica());
  a->opt_ = std::move(options);
  PeerId id{fnv1a64(a->opt_.name), a->opt_.incarnation ? a->opt_.incarnation : fresh_incarnation()};
  crdt::CausalContext applied;
  if (a->opt_.store) {
    auto loaded = a->open_store(id.incarnation);
    if (!loaded.ok()) return loaded.error();
    applied = std::move(*loaded);
    id.incarnation = a->store_->opening().incarnation;
  } else {
    a->graph_ = std::make_unique<graph::Graph>(id);
  }
  // A sampling observer pulls what changed: it subscribes to no delta, so nobody sends it any.
  if (a->opt_.replicator.sample_ns > 0) a->opt_.dds.read_deltas = false;
  a->opt_.dds.name = a->opt_.name;
  a->opt_.dds.observer = a->opt_.observer;
  a->opt_.dds.gateway = a->opt_.replicator.gateway;
  auto t = DdsTransport::create(id, a->opt_.dds);
  if (!t.ok()) return t.error();
  a->transport_ = std::move(*t);
  ReplicatorOptions ro = a->opt_.replicator;
  ro.name = a->opt_.name;
  ro.observer = a->opt_.observer;
  // The commits of one round of the loop go out as one delta interval (spin_once() flushes at
  // its end): one DDS sample (and, when signed, one signature) instead of one per commit. A
  // round ends within a tick, so a single commit leaves as soon as it did before.
  ro.coalesce = true;
  // Gossip over DDS: the participant lease already reports a crashed or cut-off peer
  // (on_peer_lost()), and DDS delivers every beat, addressed or not, to every participant (its
  // filter drops it there), so each probe costs a packet at every process. Probes then serve
  // anti-entropy and rediscovery only, and go no faster than the lease.
  // DDS discovery introduces every peer (introduce()): a newcomer's hello needs only a few
  // answers, not one from every member. Not with DDS Security: the participants DDS discovers
  // include ones that never authenticate (they can exchange no sample with this one), and a
  // peer that cannot answer would hold up every lock claim until probes declared it gone; a
  // secured replica learns its peers from authenticated samples only (hellos to everyone).
  a->introductions_ = ro.gossip && !a->opt_.dds.security;
  if (ro.gossip) ro.probe_ns = std::max(ro.probe_ns, a->opt_.dds.lease_ns);
  a->replicator_ = std::make_unique<Replicator>(*a->graph_, *a->transport_, ro);
  if (a->store_) {
    a->replicator_->restore(applied);
    a->replicator_->set_journal(a->store_.get());
  }
  graph::Graph::CommitValidator permitted;
  if (a->opt_.permissions) permitted = a->opt_.permissions->commit_check(a->graph_->replica().agent);
  if (a->opt_.schema) {  // checked after the permissions, which it wraps
    a->schema_ = std::make_unique<schema::SchemaAdmission>(a->opt_.schema, a->opt_.permissions.get());
    a->schema_->install(*a->graph_, *a->replicator_, std::move(permitted));
  } else if (a->opt_.permissions) {
    a->replicator_->set_admission(a->opt_.permissions.get());
    a->graph_->set_permission_check(std::move(permitted));
  }
  EngineOptions eo = a->opt_.engine;
  eo.clock = monotonic_ns;
  eo.seed ^= a->graph_->replica().incarnation;  // each incarnation draws its own numbers
  a->engine_ = std::make_unique<Engine>(*a->graph_, a->replicator_.get(), std::move(eo));
  // A task posted from another thread wakes a round that waits on the transport.
  a->engine_->on_posted([t = a->transport_.get()] { t->wake(); });
  const std::int64_t now = monotonic_ns();
  a->replicator_->start(now);
  a->next_tick_ = now + a->opt_.tick_ns;
  a->last_activity_ns_ = now;
  return a;
}

// Opens the store and loads the replica from it into graph_. A store that cannot be read is
// set aside, and the replica starts empty from a fresh one.
Result<crdt::CausalContext> DdsReplica::open_store(std::uint64_t incarnation) {
  const StoreOptions& so = *opt_.store;
  auto load = [&]() -> Result<crdt::CausalContext> {
    auto s = Store::open(so, opt_.name, incarnation);
    if (!s.ok()) return s.error();
    store_ = std::move(*s);
    graph_ = std::make_unique<graph::Graph>(PeerId{fnv1a64(opt_.name), store_->opening().incarnation});
    return store_->load(*graph_);
  };
  auto applied = load();
  if (applied.ok()) return applied;
  const ErrorCode c = applied.error().code;
  // Only damage is recovered from; a store in use, another agent's, or an I/O failure is the
  // caller's to resolve.
  if (c != ErrorCode::kMalformed && c != ErrorCode::kTruncated && c != ErrorCode::kUnsupportedVersion)
    return applied.error();
  store_recovery_ = applied.error();
  store_.reset();
  graph_.reset();
  if (auto aside = Store::set_aside(so.dir); !aside.ok()) return aside.error();
  return load();
}

DdsReplica::~DdsReplica() {
  keeper_.reset();  // before the transport it sends through
  if (replicator_) replicator_->leave();
  if (transport_) transport_->dispose_self();
  engine_.reset();
  replicator_.reset();
  transport_.reset();
}

void DdsReplica::spin_once(std::int64_t max_wait_ns) {
  replicator_->flush();  // commits made since the last round (outside it) leave before we block
  std::int64_t now = monotonic_ns();
  std::int64_t wait = std::min({max_wait_ns, next_tick_ - now, engine_->next_timer() - now});
  if (wait > 0 && !engine_->tasks_waiting()) transport_->wait(wait);
  bool received = false, busy = false;
  // A delta, pull or state received keeps an agent's rounds at the busy pace for a while: its
  // actions, locks and grammar checks run at ticks. A replica without them (an observer, a
  // store, a benchmark's member) is busy only while its replicator has work waiting (idle()),
  // so that a change every 100 ms does not make 100 processes tick every 10 ms.
  const bool ticks_for_samples =
      engine_->agent() != nullptr || engine_->lock_manager() != nullptr || engine_->guard() != nullptr;
  transport_->drain(
      [&](const Sample& s) {
        engine_->on_sample(s);
        received = true;
        busy = busy || (ticks_for_samples && !std::holds_alternative<SummaryMsg>(s.message));
      },
      [&](const PeerId& p, bool gone) { replicator_->on_peer_lost(p, gone); });
  if (received) engine_->pump();
  // A newcomer matched: announce ourselves now so it does not wait for a heartbeat.
  // With gossip, DDS discovery also introduces every peer (its participant carries its id and
  // name), unless the replica is secured (create()).
  if (transport_->take_new_match()) {
    for (const PeerCard& p : transport_->take_new_peers())
      if (introductions_) replicator_->introduce(p);
    replicator_->announce();
  }
  engine_->run_posted();
  engine_->run_timers();
  now = monotonic_ns();
  const auto active = [&] { return busy || replicator_->last_seq() != last_seq_seen_ || !replicator_->idle(); };
  if (now >= next_tick_) {
    engine_->step();
    if (active() || !engine_->quiet()) {
      last_activity_ns_ = now;
      last_seq_seen_ = replicator_->last_seq();
    }
    const bool quiet = opt_.quiet_tick_ns > opt_.tick_ns && now - last_activity_ns_ >= opt_.quiet_after_ns;
    next_tick_ = now + (quiet ? opt_.quiet_tick_ns : opt_.tick_ns);
  } else if (active()) {
    // Activity while the round waits its quiet period: the next round comes at the busy pace
    // (gap pulls, pull timeouts and hellos wait for it).
    last_activity_ns_ = now;
    next_tick_ = std::min(next_tick_, now + opt_.tick_ns);
  }
  replicator_->flush();  // coalesced commits (signed replicas) leave at the end of each round
}

bool DdsReplica::spin_until(const std::function<bool()>& done, std::int64_t timeout_ns) {
  const std::int64_t end = monotonic_ns() + timeout_ns;
  while (!done()) {
    std::int64_t left = end - monotonic_ns();
    if (left <= 0) return false;
    spin_once(std::min(left, kPredicateLook));
  }
  return true;
}

void DdsReplica::spin_for(std::int64_t duration_ns) {
  const std::int64_t end = monotonic_ns() + duration_ns;
  // Nothing to look at between rounds: a round waits until its next tick, timer or sample (an idle
  // replica wakes 10 times a second, not 200), and stop() wakes it.
  while (!stop_.load()) {
    const std::int64_t left = end - monotonic_ns();
    if (left <= 0) break;
    spin_once(left);
  }
}

void DdsReplica::spin() {
  while (!stop_.load()) spin_once(kSpinLook);
}

void DdsReplica::keep_alive(std::int64_t hang_ns, std::function<void(const std::string&)> warn,
                            std::function<void(const std::string&)> info) {
  keeper_.reset();
  KeeperOptions ko;
  ko.beat_ns = replicator_->options().heartbeat_ns;
  ko.hang_ns = hang_ns;
  ko.clock = monotonic_ns;
  keeper_ = std::make_unique<LivenessKeeper>(
      engine_->watch(), ko,
      [this] {
        if (auto beat = replicator_->last_heartbeat()) transport_->send(*beat);
      },
      std::move(warn), std::move(info));
}

void DdsReplica::stop() {
  stop_.store(true);
  transport_->wake();
}

}  // namespace quiver::agents::inline runtime
