#pragma once
// Private: the frame table shared between a FrameTree (its owner thread writes) and any number of
// FrameReaders (other threads read). Two mechanisms keep readers wait-free in practice and the
// writer never waiting:
//
//  1. A sequence-count latch (as in Linux's seqcount_latch) over TWO copies of every published
//     datum. The writer applies each batch to copy 0 while readers use copy 1, flips, then
//     applies it to copy 1 while readers use copy 0. A reader reads the copy the sequence number
//     points at and retries only if the sequence moved meanwhile; it never spins waiting for a
//     writer that is in the middle of an update (even one descheduled there).
//  2. Quiescent-state-based reclamation for the few objects that are replaced rather than
//     updated in place (name strings, history blocks, key tables): each reader announces the
//     reclamation epoch it last saw in its own cache line; the writer frees a retired object only
//     when every registered reader has announced a later epoch. The writer never waits: what
//     cannot be freed yet stays on its list.
//
// Every shared field is a std::atomic accessed with relaxed loads and stores (plain moves on
// x86-64), ordered by the latch's fences, so a torn read is detected and discarded, never UB.

#include <atomic>
#include <cstdint>
#include <memory>
#include <new>
#include <string>
#include <vector>

namespace quiver::kinematics::internal {

template <class T>
using Atom = std::atomic<T>;

template <class T>
inline T ld(const Atom<T>& a) {
  return a.load(std::memory_order_relaxed);
}
template <class T>
inline void st(Atom<T>& a, T v) {
  a.store(v, std::memory_order_relaxed);
}

inline constexpr std::uint32_t kChunkBits = 8;
inline constexpr std::uint32_t kChunkSlots = 1u << kChunkBits;
inline constexpr std::uint32_t kMaxChunks = 1u << 14;  // 4,194,304 frames
inline constexpr std::uint32_t kMaxSlots = kChunkSlots * kMaxChunks;
inline constexpr int kMaxReaders = 64;
inline constexpr std::int32_t kNone = -1;

/// One timestamped pose of an RT edge (X_PC) plus what interpolation towards the next sample
/// needs, precomputed by the writer: slerp(q_i, q_i+1, r) = a(r)·q_i + b(r)·sign·q_i+1 with
/// a = cos(rθ) − cosθ·sin(rθ)/sinθ and b = sin(rθ)/sinθ (θ = angle between the quaternions).
struct HistSample {
  Atom<std::int64_t> stamp;
  Atom<double> X[7];  // X_PC: qw qx qy qz, then px py pz (same layout as SlotData::X_PN)
  // Towards sample i+1 (unused on the last sample).
  Atom<double> theta;      // 0: blend linearly
  Atom<double> cos_theta;  // |<q_i, q_i+1>|
  Atom<double> inv_sin;
  Atom<double> sign;    // -1 when q_i+1 is negated to take the short way
  Atom<double> inv_dt;  // 1 / (stamp_i+1 − stamp_i)
};

/// The samples of one RT edge's current epoch (same parent), ascending by stamp, distinct stamps.
/// One allocation: the samples follow the header (one pointer less to chase per edge).
struct HistoryBlock {
  static HistoryBlock* create(std::uint32_t cap) {
    void* mem = ::operator new(sizeof(HistoryBlock) + cap * sizeof(HistSample));
    auto* h = new (mem) HistoryBlock(cap);
    for (std::uint32_t i = 0; i < cap; ++i) new (&h->samples()[i]) HistSample();
    return h;
  }
  static void destroy(HistoryBlock* h) {
    if (h == nullptr) return;
    for (std::uint32_t i = 0; i < h->capacity; ++i) h->samples()[i].~HistSample();
    h->~HistoryBlock();
    ::operator delete(h);
  }
  HistSample* samples() { return reinterpret_cast<HistSample*>(this + 1); }
  const HistSample* samples() const { return reinterpret_cast<const HistSample*>(this + 1); }

  const std::uint32_t capacity;
  Atom<std::uint32_t> size{0};

 private:
  explicit HistoryBlock(std::uint32_t cap) : capacity(cap) {}
};
static_assert(sizeof(HistoryBlock) % alignof(HistSample) == 0);

/// One frame (graph node) as readers see it, in one of the two latch copies.
struct SlotData {
  Atom<std::uint32_t> generation{0};  // bumped when the slot is freed: stale handles fail
  Atom<std::uint32_t> live{0};
  Atom<std::int32_t> parent{kNone};
  Atom<std::int32_t> root{kNone};
  Atom<std::uint32_t> depth{0};
  Atom<std::uint64_t> version{0};  // bumped whenever X_RN (or the root) changes
  Atom<std::uint64_t> id[3] = {};  // NodeId: agent, incarnation, counter
  Atom<const std::string*> name{nullptr};
  Atom<double> X_RN[12] = {};            // pose in the root frame: R row-major, then p
  Atom<double> X_PN[7] = {};             // current pose in the parent frame: qw qx qy qz x y z
  Atom<std::int64_t> stamp{0};           // of X_PN
  Atom<HistoryBlock*> history{nullptr};  // null or fewer than 2 samples: X_PN is constant
};

struct Chunk {
  SlotData copy[2][kChunkSlots];
};

/// Open-addressing table key -> slot, for names and node ids. An entry packs a 32-bit tag of the
/// key's hash (never 0) and the slot; readers confirm a tag match against the slot's key.
struct KeyTable {
  explicit KeyTable(std::uint32_t cap) : mask(cap - 1), entries(new Atom<std::uint64_t>[cap]) {
    for (std::uint32_t i = 0; i < cap; ++i) st(entries[i], std::uint64_t{0});
  }
  static constexpr std::uint64_t kEmpty = 0;
  static constexpr std::uint64_t kTomb = ~std::uint64_t{0};
  static std::uint64_t tag_of(std::uint64_t hash) { return (hash >> 32) | 1; }
  static std::uint64_t pack(std::uint64_t hash, std::uint32_t slot) {
    return (tag_of(hash) << 32) | slot;
  }

  const std::uint32_t mask;
  std::unique_ptr<Atom<std::uint64_t>[]> entries;
};

struct alignas(64) ReaderSlot {
  Atom<std::uint64_t> announced{0};  // 0: offline
  Atom<bool> used{false};
};

struct Retired {
  std::uint64_t epoch;
  void* p;
  void (*destroy)(void*);
};

/// Everything shared between the owner and the readers. Lives as long as the FrameTree or any
/// FrameReader still holds it.
struct Core {
  Core() {
    for (std::uint32_t i = 0; i < kMaxChunks; ++i) st(chunks[i], static_cast<Chunk*>(nullptr));
  }
  ~Core();
  Core(const Core&) = delete;
  Core& operator=(const Core&) = delete;

  alignas(64) Atom<std::uint64_t> seq{0};
  alignas(64) Atom<std::uint64_t> epoch{1};
  alignas(64) Atom<KeyTable*> names[2] = {};
  Atom<KeyTable*> ids[2] = {};
  Atom<Chunk*> chunks[kMaxChunks];  // inline: one load less per slot access
  ReaderSlot readers[kMaxReaders];

  // ---- Owner only ----
  std::vector<Retired> retired;
  std::uint32_t chunk_count = 0;

  SlotData* slot(int copy, std::uint32_t s) const {
    Chunk* c = chunks[s >> kChunkBits].load(std::memory_order_acquire);
    return c ? &c->copy[copy][s & (kChunkSlots - 1)] : nullptr;
  }

  void retire(HistoryBlock* p) {
    if (p)
      retired.push_back(Retired{
          ld(epoch), p, [](void* x) { HistoryBlock::destroy(static_cast<HistoryBlock*>(x)); }});
  }
  template <class T>
  void retire(T* p) {
    if (p)
      retired.push_back(Retired{ld(epoch), const_cast<void*>(static_cast<const void*>(p)),
                                [](void* x) { delete static_cast<T*>(x); }});
  }
  /// Frees what no reader can still see. Never waits.
  void reclaim();
  /// Claims a reader slot (announcing the current epoch); -1 when all are taken.
  int register_reader();
  void unregister_reader(int index);
};

/// Runs `read(copy)` until it ran entirely between two equal latch sequence numbers; `read`
/// must only read shared state and return its findings by value.
template <class F>
auto latch_read(const Core& core, F&& read) {
  for (;;) {
    const std::uint64_t s1 = core.seq.load(std::memory_order_acquire);
    auto out = read(static_cast<int>(s1 & 1));
    std::atomic_thread_fence(std::memory_order_acquire);
    if (core.seq.load(std::memory_order_relaxed) == s1) return out;
  }
}

/// As latch_read, for a `read(copy)` that fills the caller's variables (no result copies).
template <class F>
void latch_run(const Core& core, F&& read) {
  for (;;) {
    const std::uint64_t s1 = core.seq.load(std::memory_order_acquire);
    read(static_cast<int>(s1 & 1));
    std::atomic_thread_fence(std::memory_order_acquire);
    if (core.seq.load(std::memory_order_relaxed) == s1) return;
  }
}

}  // namespace quiver::kinematics::internal
