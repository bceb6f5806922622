// The viewer's messages broadcast to every open page as server-sent events through a ring: the publisher never
// waits, and a page that falls a whole ring behind is told to resync.
#include "quiver/agents/view/viewer/event_hub.h"

#include <chrono>

namespace quiver::agents::inline view::viewer {

std::uint64_t EventHub::publish(std::string event, std::string data) {
  std::uint64_t n;
  {
    std::lock_guard l(mu_);
    n = first_ + messages_.size();
    messages_.push_back("id: " + std::to_string(n) + "\nevent: " + event + "\ndata: " + data + "\n\n");
    if (messages_.size() > ring_) {
      messages_.pop_front();
      ++first_;
    }
  }
  cv_.notify_all();
  return n;
}

std::uint64_t EventHub::next() const {
  std::lock_guard l(mu_);
  return first_ + messages_.size();
}

std::string EventHub::wait(std::uint64_t& cursor, int timeout_ms) {
  std::unique_lock l(mu_);
  cv_.wait_for(l, std::chrono::milliseconds(timeout_ms),
               [&] { return closed_ || cursor < first_ || cursor < first_ + messages_.size(); });
  if (closed_) return "";
  if (cursor < first_) {
    cursor = first_ + messages_.size();
    return "event: resync\ndata: {}\n\n";
  }
  if (cursor >= first_ + messages_.size()) return "";
  return messages_[cursor++ - first_];
}

void EventHub::close() {
  {
    std::lock_guard l(mu_);
    closed_ = true;
  }
  cv_.notify_all();
}

bool EventHub::closed() const {
  std::lock_guard l(mu_);
  return closed_;
}

}  // namespace quiver::agents::inline view::viewer
