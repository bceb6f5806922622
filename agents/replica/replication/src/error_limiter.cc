// Log lines rate-limited by kind: the first few of a period emitted, the rest counted into one summary line.
#include "quiver/agents/replica/replication/error_limiter.h"

namespace quiver::agents::inline replica {

void ErrorLimiter::report(const std::string& kind, const std::string& line, std::int64_t now_ns) {
  ++seen_;
  tick(now_ns);
  auto [it, fresh] = kinds_.try_emplace(kind);
  Kind& k = it->second;
  if (fresh || now_ns - k.window_start >= period_ns_) {
    k.window_start = now_ns;
    k.emitted = 0;
  }
  if (k.emitted < burst_) {
    ++k.emitted;
    emit_(line);
    return;
  }
  ++k.held;
  ++suppressed_;
  k.last = line;
}

void ErrorLimiter::tick(std::int64_t now_ns) {
  for (auto& [kind, k] : kinds_) {
    if (k.held == 0 || now_ns - k.window_start < period_ns_) continue;
    emit_(std::to_string(k.held) + " more " + kind + " in the last " + std::to_string(period_ns_ / 1'000'000'000) +
          " s; the last: " + k.last);
    k.held = 0;
    k.last.clear();
    k.window_start = now_ns;
    k.emitted = 0;
  }
}

}  // namespace quiver::agents
