// Stage marks for `quiver bench dds --stages` (stage_marks.h).
#include "quiver/base/stage_marks.h"

#include <array>
#include <atomic>
#include <chrono>

namespace quiver::inline base::stage_marks {
namespace {

constexpr int kStages = static_cast<int>(Stage::kCount);
std::atomic<bool> g_on{false};
std::array<std::atomic<std::int64_t>, kStages> g_at{};

}  // namespace

void enable() { g_on.store(true, std::memory_order_relaxed); }

void mark(Stage s) {
  if (!g_on.load(std::memory_order_relaxed)) return;
  const auto t = std::chrono::steady_clock::now().time_since_epoch();
  g_at[static_cast<int>(s)].store(std::chrono::duration_cast<std::chrono::nanoseconds>(t).count(),
                                  std::memory_order_relaxed);
}

std::int64_t at(Stage s) { return g_at[static_cast<int>(s)].load(std::memory_order_relaxed); }

}  // namespace quiver::inline base::stage_marks
