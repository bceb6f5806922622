// The engine's marks of user code, read by a watcher thread through a seqlock.
#include "quiver/agents/runtime/engine/callback_watch.h"

namespace quiver::agents::inline runtime {

CallbackWatch::Scope CallbackWatch::enter(const char* callback, const std::string* action, std::int64_t now_ns) {
  if (depth_++ == 0) {
    seq_.fetch_add(1, std::memory_order_acq_rel);
    since_.store(now_ns, std::memory_order_relaxed);
    call_.fetch_add(1, std::memory_order_relaxed);
    callback_.store(callback, std::memory_order_relaxed);
    action_.store(action, std::memory_order_relaxed);
    busy_.store(true, std::memory_order_relaxed);
    seq_.fetch_add(1, std::memory_order_release);
  }
  return Scope(this);
}

void CallbackWatch::leave() {
  if (--depth_ == 0) {
    seq_.fetch_add(1, std::memory_order_acq_rel);
    busy_.store(false, std::memory_order_relaxed);
    action_.store(nullptr, std::memory_order_relaxed);
    seq_.fetch_add(1, std::memory_order_release);
  }
}

CallbackWatch::Snapshot CallbackWatch::snapshot() const {
  for (;;) {
    const std::uint64_t before = seq_.load(std::memory_order_acquire);
    if (before & 1) continue;  // the engine is writing: a few instructions
    Snapshot s;
    s.busy = busy_.load(std::memory_order_relaxed);
    s.since_ns = since_.load(std::memory_order_relaxed);
    s.call = call_.load(std::memory_order_relaxed);
    s.callback = callback_.load(std::memory_order_relaxed);
    const std::string* action = action_.load(std::memory_order_relaxed);
    std::atomic_thread_fence(std::memory_order_acquire);
    if (seq_.load(std::memory_order_relaxed) != before) continue;
    // The action outlives the scope that named it, and the scope is still open (seq unchanged).
    if (s.busy && action != nullptr) s.action = *action;
    return s;
  }
}

}  // namespace quiver::agents::inline runtime
