#pragma once
/// @file
/// Broadcasts the viewer's messages to every open page (server-sent events) without ever making
/// the publisher wait: messages go into a ring; each connection reads at its own pace, and one
/// that falls a whole ring behind is told to reload ("resync") instead of holding anyone up.
/// Thread-safe.

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>
#include <string>

namespace quiver::agents::inline view::viewer {

class EventHub {
 public:
  explicit EventHub(std::size_t ring = 1024) : ring_(ring) {}

  /// Adds a message (an SSE event name and its data, one line of JSON). @returns its number.
  std::uint64_t publish(std::string event, std::string data);
  /// The number the next message will get (a new connection starts reading there).
  std::uint64_t next() const;
  /// Waits up to `timeout_ms` for message `cursor` and returns it framed as an SSE event (with
  /// "id:"), advancing `cursor`; "" on timeout. A cursor that fell out of the ring gets one
  /// "resync" event and moves to the newest message. After close(): returns "" at once.
  std::string wait(std::uint64_t& cursor, int timeout_ms);
  /// Wakes every waiter for good (the server is stopping).
  void close();
  bool closed() const;

 private:
  std::size_t ring_;
  mutable std::mutex mu_;
  std::condition_variable cv_;
  std::deque<std::string> messages_;  // framed, numbers first_ .. first_ + size - 1
  std::uint64_t first_ = 0;
  bool closed_ = false;
};

}  // namespace quiver::agents::inline view::viewer
