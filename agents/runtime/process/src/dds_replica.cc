#include "quiver/agents/runtime/process/dds_replica.h"

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
  auto t = DdsTransport::create(id, a->opt_.dds);
  if (!t.ok()) return t.error();
  a->transport_ = std::move(*t);
  ReplicatorOptions ro = a->opt_.replicator;
  ro.name = a->opt_.name;
  ro.observer = a->opt_.observer;
  // Signed deltas: the commits of one round of the loop go out as one delta interval, one
  // signature (spin_once() flushes at its end), instead of one signature per commit.
  if (a->opt_.permissions) ro.coalesce = true;
  a->replicator_ = std::make_unique<Replicator>(*a->graph_, *a->transport_, ro);
  if (a->store_) {
    a->replicator_->restore(applied);
    a->replicator_->set_journal(a->store_.get());
  }
  if (a->opt_.permissions) {
    a->replicator_->set_admission(a->opt_.permissions.get());
    a->graph_->set_permission_check(a->opt_.permissions->commit_check(a->graph_->replica().agent));
  }
  const std::int64_t now = monotonic_ns();
  a->replicator_->start(now);
  a->next_tick_ = now + a->opt_.tick_ns;
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
  if (replicator_) replicator_->leave();
  if (transport_) transport_->dispose_self();
  replicator_.reset();
  transport_.reset();
}

void DdsReplica::spin_once(std::int64_t max_wait_ns) {
  replicator_->flush();  // commits made since the last round (outside it) leave before we block
  std::int64_t now = monotonic_ns();
  std::int64_t wait = std::min(max_wait_ns, next_tick_ - now);
  if (!timers_.empty()) wait = std::min(wait, timers_.top().due - now);
  if (wait > 0) transport_->wait(wait);
  transport_->drain([&](const Sample& s) { replicator_->on_sample(s, monotonic_ns()); },
                    [&](const PeerId& p, bool gone) { replicator_->on_peer_lost(p, gone); });
  // A newcomer matched: announce ourselves now so it does not wait for a heartbeat.
  if (transport_->take_new_match()) replicator_->announce();
  std::vector<std::function<void()>>
      tasks;  // empty vectors own no memory: nothing allocated when idle
  {
    std::lock_guard<std::mutex> lock(mu_);
    tasks.swap(posted_);
  }
  for (auto& f : tasks) f();
  now = monotonic_ns();
  run_timers(now);
  if (now >= next_tick_) {
    replicator_->tick(now);
    next_tick_ = now + opt_.tick_ns;
  }
  replicator_->flush();  // coalesced commits (signed replicas) leave at the end of each round
}

bool DdsReplica::spin_until(const std::function<bool()>& done, std::int64_t timeout_ns) {
  const std::int64_t end = monotonic_ns() + timeout_ns;
  while (!done()) {
    std::int64_t left = end - monotonic_ns();
    if (left <= 0) return false;
    spin_once(std::min<std::int64_t>(left, 5'000'000));
  }
  return true;
}

void DdsReplica::spin_for(std::int64_t duration_ns) {
  const std::int64_t end = monotonic_ns() + duration_ns;
  while (monotonic_ns() < end && !stop_.load()) spin_once(std::min<std::int64_t>(end - monotonic_ns(), 5'000'000));
}

void DdsReplica::spin() {
  while (!stop_.load()) spin_once(50'000'000);
}

void DdsReplica::post(std::function<void()> fn) {
  {
    std::lock_guard<std::mutex> lock(mu_);
    posted_.push_back(std::move(fn));
  }
  transport_->wake();
}

DdsReplica::TimerId DdsReplica::after(std::int64_t delay_ns, std::function<void()> fn) {
  const TimerId id = next_timer_++;
  timer_fns_.emplace(id, std::move(fn));
  timers_.push(Timer{monotonic_ns() + std::max<std::int64_t>(delay_ns, 0), id, 0});
  return id;
}

DdsReplica::TimerId DdsReplica::every(std::int64_t period_ns, std::function<void()> fn) {
  if (period_ns <= 0) period_ns = 1;
  const TimerId id = next_timer_++;
  timer_fns_.emplace(id, std::move(fn));
  timers_.push(Timer{monotonic_ns() + period_ns, id, period_ns});
  return id;
}

void DdsReplica::cancel(TimerId id) { timer_fns_.erase(id); }

void DdsReplica::run_timers(std::int64_t now) {
  while (!timers_.empty() && timers_.top().due <= now) {
    Timer t = timers_.top();
    timers_.pop();
    auto it = timer_fns_.find(t.id);
    if (it == timer_fns_.end()) continue;  // cancelled
    std::function<void()> fn = t.period > 0 ? it->second : std::move(it->second);
    if (t.period > 0) {
      // The next due time after now: a slow round does not make the timer fire in a burst.
      t.due += t.period * ((now - t.due) / t.period + 1);
      timers_.push(t);
    } else {
      timer_fns_.erase(it);
    }
    fn();
  }
}

void DdsReplica::stop() {
  stop_.store(true);
  transport_->wake();
}

}  // namespace quiver::agents
