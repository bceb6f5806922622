// Stage marks for `quiver bench dds --stages` (stage_marks.h).
#include "quiver/base/stage_marks.h"

#include <atomic>
#include <chrono>

namespace quiver::inline base::stage_marks {
namespace {

constexpr int kStages = static_cast<int>(Stage::kCount);
std::atomic<bool> g_on{false};
std::array<std::atomic<std::int64_t>, kStages> g_at{};

}  // namespace

void enable() { g_on.store(true, std::memory_order_relaxed); }

bool enabled() { return g_on.load(std::memory_order_relaxed); }

void mark(Stage s) {
  if (!g_on.load(std::memory_order_relaxed)) return;
  const auto t = std::chrono::steady_clock::now().time_since_epoch();
  g_at[static_cast<int>(s)].store(std::chrono::duration_cast<std::chrono::nanoseconds>(t).count(),
                                  std::memory_order_relaxed);
}

std::array<std::int64_t, kStages> latest() {
  std::array<std::int64_t, kStages> out{};
  for (int i = 0; i < kStages; ++i) out[i] = g_at[i].load(std::memory_order_relaxed);
  return out;
}

const char* name(Stage s) {
  switch (s) {
    case Stage::kEncoded: return "encoded";
    case Stage::kSigned: return "signed";
    case Stage::kWritten: return "written";
    case Stage::kWoken: return "woken";
    case Stage::kTaken: return "taken";
    case Stage::kDecoded: return "decoded";
    case Stage::kAdmitted: return "admitted";
    case Stage::kMerging: return "merging";
    case Stage::kCount: break;
  }
  return "?";
}

}  // namespace quiver::inline base::stage_marks
