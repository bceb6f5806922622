// An engine's timers: a heap of due times over a table of functions (cancelled ones are skipped).
#include "quiver/agents/runtime/engine/timer_queue.h"

#include <algorithm>
#include <climits>

namespace quiver::agents::inline runtime {

TimerId TimerQueue::at(std::int64_t due, std::function<void()> fn) {
  const TimerId id = next_++;
  fns_.emplace(id, std::move(fn));
  heap_.push(Timer{due, id, 0});
  return id;
}

TimerId TimerQueue::every(std::int64_t first, std::int64_t period_ns, std::function<void()> fn) {
  const TimerId id = next_++;
  fns_.emplace(id, std::move(fn));
  heap_.push(Timer{first, id, std::max<std::int64_t>(1, period_ns)});
  return id;
}

void TimerQueue::cancel(TimerId id) { fns_.erase(id); }

std::int64_t TimerQueue::next_due() const {
  // Cancelled timers at the top only make a wait end early.
  return heap_.empty() ? INT64_MAX : heap_.top().due;
}

std::size_t TimerQueue::run_due(std::int64_t now, const std::function<bool()>& more) {
  std::size_t ran = 0;
  while (!heap_.empty() && heap_.top().due <= now) {
    if (ran > 0 && more && !more()) break;
    Timer t = heap_.top();
    heap_.pop();
    auto it = fns_.find(t.id);
    if (it == fns_.end()) continue;  // cancelled
    std::function<void()> fn;
    if (t.period > 0) {
      fn = it->second;
      // One period on; a round that fell a whole period behind starts again from now, so a slow
      // round never makes a timer fire in a burst.
      t.due += t.period;
      if (t.due <= now) t.due = now + t.period;
      heap_.push(t);
    } else {
      fn = std::move(it->second);
      fns_.erase(it);
    }
    fn();
    ++ran;
  }
  return ran;
}

}  // namespace quiver::agents::inline runtime
