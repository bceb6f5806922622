#include "quiver/agents/replication/error_limiter.h"

namespace quiver::agents {

void ErrorLimiter::report(const Error& e, std::int64_t now_ns) {
  ++seen_;
  auto [it, fresh] = kinds_.try_emplace(e.code);
  Kind& k = it->second;
  if (fresh || now_ns - k.window_start >= period_ns_) {
    tick(now_ns);
    k.window_start = now_ns;
    emit_(e.to_string());
    return;
  }
  ++k.held;
  ++suppressed_;
  k.last = e.message;
}

void ErrorLimiter::tick(std::int64_t now_ns) {
  for (auto& [code, k] : kinds_) {
    if (k.held == 0 || now_ns - k.window_start < period_ns_) continue;
    emit_(std::to_string(k.held) + " more " + to_string(code) + " errors in the last " +
          std::to_string(period_ns_ / 1'000'000'000) + " s; the last: " + k.last);
    k.held = 0;
    k.last.clear();
    k.window_start = now_ns;
  }
}

}  // namespace quiver::agents
