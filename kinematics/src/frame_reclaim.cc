// The shared frame table's lifetime and quiescent-state reclamation: freeing what no reader can
// still see, and the registry of reader slots that announce their epochs.

#include <unordered_set>

#include "frame_store.h"

namespace quiver::kinematics {

namespace internal {

Core::~Core() {
  for (const Retired& r : retired) r.destroy(r.p);
  for (int c = 0; c < 2; ++c) {
    delete names[c].load();
    delete ids[c].load();
  }
  std::unordered_set<const std::string*> strings;
  for (std::uint32_t k = 0; k < kMaxChunks; ++k) {
    Chunk* ch = chunks[k].load();
    if (ch == nullptr) continue;
    for (int c = 0; c < 2; ++c)
      for (SlotData& d : ch->copy[c]) {
        HistoryBlock::destroy(d.history.load());
        if (const std::string* s = d.name.load()) strings.insert(s);
      }
    delete ch;
  }
  for (const std::string* s : strings) delete s;
}

void Core::reclaim() {
  if (retired.empty()) return;
  std::uint64_t cur = epoch.load(std::memory_order_relaxed);
  for (const Retired& r : retired)
    if (r.epoch == cur) {
      // Everything retired so far is unlinked from both copies: readers that see the new epoch
      // cannot reach it.
      epoch.store(++cur, std::memory_order_seq_cst);
      break;
    }
  std::atomic_thread_fence(std::memory_order_seq_cst);
  std::uint64_t min = cur;
  for (const ReaderSlot& r : readers) {
    if (!r.used.load(std::memory_order_acquire)) continue;
    const std::uint64_t a = r.announced.load(std::memory_order_acquire);
    if (a != 0 && a < min) min = a;
  }
  std::size_t kept = 0;
  for (std::size_t i = 0; i < retired.size(); ++i) {
    if (retired[i].epoch < min)
      retired[i].destroy(retired[i].p);
    else
      retired[kept++] = retired[i];
  }
  retired.resize(kept);
}

int Core::register_reader() {
  for (int i = 0; i < kMaxReaders; ++i) {
    bool expected = false;
    if (readers[i].used.compare_exchange_strong(expected, true, std::memory_order_acq_rel))
      return i;
  }
  return -1;
}

void Core::unregister_reader(int index) {
  readers[index].announced.store(0, std::memory_order_release);
  readers[index].used.store(false, std::memory_order_release);
}

}  // namespace internal

}  // namespace quiver::kinematics
