// The keeper's thread: heartbeats on a blocked agent's behalf, and one report per hung callback.
#include "quiver/agents/runtime/engine/liveness_keeper.h"

#include <algorithm>
#include <chrono>
#include <cstdio>

namespace quiver::agents::inline runtime {
namespace {

std::string seconds(std::int64_t ns) {
  char b[32];
  std::snprintf(b, sizeof b, "%.1f s", static_cast<double>(ns) / 1e9);
  return b;
}

}  // namespace

std::string describe_callback(const CallbackWatch::Snapshot& s) {
  if (s.action.empty()) return s.callback;
  return "action '" + s.action + "' " + s.callback;
}

LivenessKeeper::LivenessKeeper(const CallbackWatch& watch, KeeperOptions o, std::function<void()> beat,
                               std::function<void(const std::string&)> warn,
                               std::function<void(const std::string&)> info)
    : watch_(watch), opt_(std::move(o)), beat_(std::move(beat)), warn_(std::move(warn)), info_(std::move(info)) {
  thread_ = std::thread([this] { loop(); });
}

LivenessKeeper::~LivenessKeeper() {
  {
    std::lock_guard<std::mutex> lock(mu_);
    stop_ = true;
  }
  cv_.notify_all();
  thread_.join();
}

std::uint64_t LivenessKeeper::beats() const {
  std::lock_guard<std::mutex> lock(mu_);
  return beats_;
}

std::uint64_t LivenessKeeper::hangs() const {
  std::lock_guard<std::mutex> lock(mu_);
  return hangs_;
}

void LivenessKeeper::loop() {
  // Four looks per heartbeat period: a blocked agent's heartbeats are late by a quarter period.
  const auto period = std::chrono::nanoseconds(std::max<std::int64_t>(opt_.beat_ns / 4, 1'000'000));
  std::unique_lock<std::mutex> lock(mu_);
  while (!cv_.wait_for(lock, period, [this] { return stop_; })) {
    lock.unlock();
    check(opt_.clock());
    lock.lock();
  }
}

void LivenessKeeper::check(std::int64_t now) {
  const CallbackWatch::Snapshot s = watch_.snapshot();
  if (reported_call_ != 0 && !(s.busy && s.call == reported_call_)) {
    if (info_)
      info_("agent '" + watch_.agent() + "': " + reported_what_ + " came back after about " +
            seconds(now - reported_since_));
    reported_call_ = 0;
  }
  if (!s.busy) return;
  const std::int64_t busy_for = now - s.since_ns;
  if (busy_for >= opt_.beat_ns && now - last_beat_ >= opt_.beat_ns) {
    last_beat_ = now;
    beat_();
    std::lock_guard<std::mutex> lock(mu_);
    ++beats_;
  }
  if (opt_.hang_ns > 0 && busy_for >= opt_.hang_ns && reported_call_ != s.call) {
    reported_call_ = s.call;
    reported_since_ = s.since_ns;
    reported_what_ = describe_callback(s);
    warn_("agent '" + watch_.agent() + "': " + reported_what_ + " has not returned for " + seconds(busy_for) +
          " (hung?). Its peers still hear it and its locks hold, but it joins nothing and runs nothing else "
          "until it returns; long work belongs in a job (run_job), off the agent's thread");
    std::lock_guard<std::mutex> lock(mu_);
    ++hangs_;
  }
}

}  // namespace quiver::agents::inline runtime
