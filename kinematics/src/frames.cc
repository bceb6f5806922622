// FrameTree (owner side: mirrors the graph's RT tree, recomputes the per-frame root-pose cache for
// changed subtrees, publishes through the latch) and FrameReader (lock-free lookups).

#include "quiver/kinematics/frames.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <unordered_set>

#include "frame_store.h"
#include "pose_math.h"
#include "quiver/base/hash.h"

namespace quiver::kinematics {

using graph::NodeId;
using internal::Atom;
using internal::Core;
using internal::HistoryBlock;
using internal::HistSample;
using internal::KeyTable;
using internal::kNone;
using internal::ld;
using internal::QP;
using internal::SlotData;
using internal::st;

// ------------------------------------------------------------------------------------ Core

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

namespace {

// ------------------------------------------------------------------------------------ hashing

std::uint64_t hash_name(std::string_view s) { return mix64(fnv1a64(s)); }

std::uint64_t hash_id(const NodeId& id) { return mix64(hash_value(id.dot) + 0x51ed27ULL); }

std::uint32_t pow2_at_least(std::uint64_t n) {
  return static_cast<std::uint32_t>(std::bit_ceil(std::max<std::uint64_t>(n, 16)));
}

// ------------------------------------------------------------------------------------ reads

enum class Code : std::uint8_t {
  kOk,
  kNotFound,
  kEmpty,
  kNotConnected,
  kPast,
  kFuture,
  kNoParent,
  kTorn
};

/// Pointers to immutable objects (name strings, history blocks) are published with release
/// stores and read with acquire loads.
const std::string* load_name(const SlotData* d) { return d->name.load(std::memory_order_acquire); }

bool slot_matches_name(const SlotData* d, std::string_view name) {
  const std::string* n = d->name.load(std::memory_order_acquire);
  return n != nullptr && std::string_view(*n) == name;
}

bool slot_matches_id(const SlotData* d, const NodeId& id) {
  return ld(d->id[0]) == id.dot.replica.agent && ld(d->id[1]) == id.dot.replica.incarnation &&
         ld(d->id[2]) == id.dot.counter;
}

template <class Match>
Code probe(const Core& core, int c, const Atom<KeyTable*>& table_ptr, std::uint64_t h,
           Match&& match, std::uint32_t* out) {
  const KeyTable* t = table_ptr.load(std::memory_order_acquire);
  if (t == nullptr) return Code::kNotFound;
  const std::uint64_t tag = KeyTable::tag_of(h);
  std::uint32_t i = static_cast<std::uint32_t>(h) & t->mask;
  for (std::uint32_t n = 0; n <= t->mask; ++n, i = (i + 1) & t->mask) {
    const std::uint64_t e = ld(t->entries[i]);
    if (e == KeyTable::kEmpty) return Code::kNotFound;
    if (e == KeyTable::kTomb || (e >> 32) != tag) continue;
    const std::uint32_t s = static_cast<std::uint32_t>(e);
    if (s >= internal::kMaxSlots) return Code::kTorn;
    const SlotData* d = core.slot(c, s);
    if (d == nullptr) return Code::kTorn;
    if (ld(d->live) && match(d)) {
      *out = s;
      return Code::kOk;
    }
  }
  return Code::kNotFound;
}

/// Resolves a frame reference in copy `c`.
Code resolve(const Core& core, int c, const FrameRef& f, std::uint32_t* slot) {
  switch (f.kind()) {
    case FrameRef::Kind::kName: {
      std::string_view name = f.name();
      if (name.empty()) return Code::kEmpty;
      return probe(
          core, c, core.names[c], hash_name(name),
          [&](const SlotData* d) { return slot_matches_name(d, name); }, slot);
    }
    case FrameRef::Kind::kId: {
      NodeId id = f.id();
      if (id.is_null()) return Code::kEmpty;
      return probe(
          core, c, core.ids[c], hash_id(id),
          [&](const SlotData* d) { return slot_matches_id(d, id); }, slot);
    }
    case FrameRef::Kind::kHandle: {
      Frame h = f.frame();
      if (h.is_null()) return Code::kEmpty;
      if (h.slot >= internal::kMaxSlots) return Code::kNotFound;
      const SlotData* d = core.slot(c, h.slot);
      if (d == nullptr || !ld(d->live) || ld(d->generation) != h.generation) return Code::kNotFound;
      *slot = h.slot;
      return Code::kOk;
    }
  }
  return Code::kNotFound;
}

void load_root_pose(const SlotData* d, double* R, double* p) {
  for (int i = 0; i < 9; ++i) R[i] = ld(d->X_RN[i]);
  for (int i = 0; i < 3; ++i) p[i] = ld(d->X_RN[9 + i]);
}

/// What one latch attempt found; messages are built from it afterwards.
struct Raw {
  Code code = Code::kOk;
  int which = 0;  // kNotFound / kEmpty: 0 = A, 1 = B
  std::uint32_t sa = 0, sb = 0;
  const std::string* name_a = nullptr;
  const std::string* name_b = nullptr;
  const std::string* root_a = nullptr;
  const std::string* root_b = nullptr;
  const std::string* edge_child = nullptr;
  const std::string* edge_parent = nullptr;
  Time bound = 0;
  double R[9];  // the result X_AB
  double p[3];
};

/// Where one edge's pose at time t comes from: X = slerp/lerp(X0, X1, r) with the interval's
/// precomputed angle data. A constant edge or an exact sample has X0 = X1, r = 0, θ = 0.
struct EdgeSel {
  const Atom<double>* X0;  // qw qx qy qz px py pz
  const Atom<double>* X1;
  double r, theta, cos_theta, inv_sin, sign;
};

/// How many samples of a (possibly null) published history block may be read.
[[gnu::always_inline]] inline std::uint32_t history_size(const HistoryBlock* h) {
  return h ? std::min(ld(h->size), h->capacity) : 0;
}

/// Finds the samples of a slot's edge bracketing time t.
[[gnu::always_inline]] inline Code select_edge(const SlotData* d, Time t, EdgeSel& e, Time* bound) {
  const HistoryBlock* h = d->history.load(std::memory_order_acquire);
  const std::uint32_t n = history_size(h);
  e.r = e.theta = e.inv_sin = 0.0;
  e.cos_theta = e.sign = 1.0;
  if (n < 2) {
    const Time stamp = ld(d->stamp);
    if (t < stamp) {
      *bound = stamp;
      return Code::kPast;
    }
    e.X0 = e.X1 = d->X_PN;
    return Code::kOk;
  }
  const HistSample* s = h->samples();
  const Time first = ld(s[0].stamp);
  const Time last = ld(s[n - 1].stamp);
  if (t < first) {
    *bound = first;
    return Code::kPast;
  }
  if (t > last) {
    *bound = last;
    return Code::kFuture;
  }
  // The greatest i with stamp_i <= t.
  std::uint32_t lo = 0, hi = n - 1;
  while (lo < hi) {
    const std::uint32_t mid = (lo + hi + 1) / 2;
    if (ld(s[mid].stamp) <= t)
      lo = mid;
    else
      hi = mid - 1;
  }
  const HistSample& a = s[lo];
  const Time ta = ld(a.stamp);
  e.X0 = e.X1 = a.X;
  if (ta == t || lo + 1 >= n) return Code::kOk;
  e.X1 = s[lo + 1].X;
  e.r = static_cast<double>(t - ta) * ld(a.inv_dt);
  e.theta = ld(a.theta);
  e.cos_theta = ld(a.cos_theta);
  e.inv_sin = ld(a.inv_sin);
  e.sign = ld(a.sign);
  return Code::kOk;
}

/// One edge's interpolation inputs, as doubles or as two-lane vectors (T = v2d: the walks up
/// from A and from B in lock step, sharing every instruction).
typedef double v2d __attribute__((vector_size(16)));
template <class T>
struct Interp {
  T X0[7], X1[7];
  T r, theta, cos_theta, inv_sin, sign;
};

[[gnu::always_inline]] inline void gather(const EdgeSel& e, Interp<double>& in) {
  for (int i = 0; i < 7; ++i) {
    in.X0[i] = ld(e.X0[i]);
    in.X1[i] = ld(e.X1[i]);
  }
  in.r = e.r;
  in.theta = e.theta;
  in.cos_theta = e.cos_theta;
  in.inv_sin = e.inv_sin;
  in.sign = e.sign;
}

[[gnu::always_inline]] inline void gather(const EdgeSel& a, const EdgeSel& b, Interp<v2d>& in) {
  for (int i = 0; i < 7; ++i) {
    in.X0[i] = v2d{ld(a.X0[i]), ld(b.X0[i])};
    in.X1[i] = v2d{ld(a.X1[i]), ld(b.X1[i])};
  }
  in.r = v2d{a.r, b.r};
  in.theta = v2d{a.theta, b.theta};
  in.cos_theta = v2d{a.cos_theta, b.cos_theta};
  in.inv_sin = v2d{a.inv_sin, b.inv_sin};
  in.sign = v2d{a.sign, b.sign};
}

inline double select_linear(double theta, double if_linear, double otherwise) {
  return theta == 0.0 ? if_linear : otherwise;
}
inline v2d select_linear(v2d theta, v2d if_linear, v2d otherwise) {
  return theta == 0.0 ? if_linear : otherwise;
}

/// acc <- X_PC(t) · acc (acc: q[4] then p[3]), X_PC interpolated from `e`. The same sequence of
/// IEEE operations for T = double and for each lane of T = v2d, so both give the same bits.
template <class T>
[[gnu::always_inline]] inline void interp_compose(T* acc, const Interp<T>& e) {
  // slerp weights: a = sin((1−r)θ)/sinθ = cos rθ − cosθ·sin rθ/sinθ, b = sin rθ/sinθ; or a
  // linear blend (1 − r, r) when θ = 0.
  T sn, cs;
  internal::sincos_quarter<T>(e.r * e.theta, &sn, &cs);
  T kb = sn * e.inv_sin;
  T ka = cs - e.cos_theta * kb;
  ka = select_linear(e.theta, 1.0 - e.r, ka);
  kb = select_linear(e.theta, e.r, kb) * e.sign;
  T q[4], p[3];
  for (int i = 0; i < 4; ++i) q[i] = ka * e.X0[i] + kb * e.X1[i];
  for (int i = 0; i < 3; ++i) p[i] = e.X0[4 + i] + e.r * (e.X1[4 + i] - e.X0[4 + i]);
  // q_acc <- q ⊗ q_acc, p_acc <- p + R(q) p_acc, in place (both helpers read all their inputs
  // before writing; no temporaries for the compiler to copy around).
  internal::quat_mul<T>(q, acc, acc);
  internal::quat_rotate<T>(q, acc + 4, acc + 4);
  for (int i = 0; i < 3; ++i) acc[4 + i] = p[i] + acc[4 + i];
}

/// Resolves both ends into raw.sa / raw.sb; on failure records which end and why.
bool resolve_pair(const Core& core, int c, const FrameRef& A, const FrameRef& B, Raw& raw) {
  raw.code = Code::kOk;
  const FrameRef* ends[2] = {&A, &B};
  std::uint32_t* slots[2] = {&raw.sa, &raw.sb};
  for (int i = 0; i < 2; ++i) {
    const Code k = resolve(core, c, *ends[i], slots[i]);
    if (k != Code::kOk) {
      raw.code = k;
      raw.which = i;
      return false;
    }
  }
  return true;
}

/// Latest-time X_AB in copy c.
void read_latest(const Core& core, int c, const FrameRef& A, const FrameRef& B, Raw& raw) {
  if (!resolve_pair(core, c, A, B, raw)) return;
  const SlotData* a = core.slot(c, raw.sa);
  const SlotData* b = core.slot(c, raw.sb);
  const std::int32_t root_a = ld(a->root);
  const std::int32_t root_b = ld(b->root);
  if (root_a != root_b) {
    raw.code = Code::kNotConnected;
    raw.name_a = load_name(a);
    raw.name_b = load_name(b);
    const SlotData* ra = root_a >= 0 ? core.slot(c, static_cast<std::uint32_t>(root_a)) : nullptr;
    const SlotData* rb = root_b >= 0 ? core.slot(c, static_cast<std::uint32_t>(root_b)) : nullptr;
    raw.root_a = ra ? load_name(ra) : nullptr;
    raw.root_b = rb ? load_name(rb) : nullptr;
    return;
  }
  double Ra[9], pa[3], Rb[9], pb[3];
  load_root_pose(a, Ra, pa);
  load_root_pose(b, Rb, pb);
  // X_AB = X_RA⁻¹ X_RB: R_AB = R_RAᵀ R_RB, p_AB = R_RAᵀ (p_RB − p_RA).
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      raw.R[i * 3 + j] = Ra[0 * 3 + i] * Rb[0 * 3 + j] + Ra[1 * 3 + i] * Rb[1 * 3 + j] +
                         Ra[2 * 3 + i] * Rb[2 * 3 + j];
  const double d0 = pb[0] - pa[0], d1 = pb[1] - pa[1], d2 = pb[2] - pa[2];
  raw.p[0] = Ra[0] * d0 + Ra[3] * d1 + Ra[6] * d2;
  raw.p[1] = Ra[1] * d0 + Ra[4] * d1 + Ra[7] * d2;
  raw.p[2] = Ra[2] * d0 + Ra[5] * d1 + Ra[8] * d2;
  return;
}

/// X_AB at time t in copy c: both sides walk up to their lowest common ancestor L, the deeper
/// one alone first, then both in lock step.
void read_at(const Core& core, int c, const FrameRef& A, const FrameRef& B, Time t, Raw& raw) {
  if (!resolve_pair(core, c, A, B, raw)) return;
  const SlotData* da = core.slot(c, raw.sa);
  const SlotData* db = core.slot(c, raw.sb);
  if (ld(da->root) != ld(db->root)) return read_latest(core, c, A, B, raw);  // builds the message
  double acc_a[7] = {1, 0, 0, 0, 0, 0, 0};  // X_LA, L the current ancestor of A (q then p)
  double acc_b[7] = {1, 0, 0, 0, 0, 0, 0};  // X_LB
  std::uint32_t slot[2] = {raw.sa, raw.sb};
  std::uint32_t depth[2] = {ld(da->depth), ld(db->depth)};
  // Selects side k's next edge and moves that side up; false (raw filled in) on failure.
  auto advance = [&](int side, EdgeSel& e) __attribute__((always_inline))->bool {
    const SlotData* d = core.slot(c, slot[side]);
    const std::int32_t p = ld(d->parent);
    const SlotData* pd = p >= 0 ? core.slot(c, static_cast<std::uint32_t>(p)) : nullptr;
    if (pd == nullptr || depth[side] == 0) {
      raw.code = Code::kTorn;
      return false;
    }
    Code k = select_edge(d, t, e, &raw.bound);
    if (k != Code::kOk) {
      raw.code = k;
      raw.edge_child = d->name.load(std::memory_order_acquire);
      raw.edge_parent = pd->name.load(std::memory_order_acquire);
      return false;
    }
    slot[side] = static_cast<std::uint32_t>(p);
    --depth[side];
    return true;
  };
  EdgeSel ea, eb;
  Interp<double> one;
  while (depth[0] > depth[1]) {
    if (!advance(0, ea)) return;
    gather(ea, one);
    interp_compose<double>(acc_a, one);
  }
  while (depth[1] > depth[0]) {
    if (!advance(1, eb)) return;
    gather(eb, one);
    interp_compose<double>(acc_b, one);
  }
  if (slot[0] != slot[1]) {
    v2d acc[7];
    for (int i = 0; i < 7; ++i) acc[i] = v2d{acc_a[i], acc_b[i]};
    Interp<v2d> two;
    while (slot[0] != slot[1]) {
      if (!advance(0, ea) || !advance(1, eb)) return;
      gather(ea, eb, two);
      interp_compose<v2d>(acc, two);
    }
    for (int i = 0; i < 7; ++i) {
      acc_a[i] = acc[i][0];
      acc_b[i] = acc[i][1];
    }
  }
  QP X_LA, X_LB;
  for (int i = 0; i < 4; ++i) {
    X_LA.q[i] = acc_a[i];
    X_LB.q[i] = acc_b[i];
  }
  for (int i = 0; i < 3; ++i) {
    X_LA.p[i] = acc_a[4 + i];
    X_LB.p[i] = acc_b[4 + i];
  }
  const QP X_AB = internal::compose(internal::inverse(X_LA), X_LB);
  internal::quat_to_matrix(X_AB.q, raw.R);
  for (int i = 0; i < 3; ++i) raw.p[i] = X_AB.p[i];
  return;
}

std::string quoted(const std::string* s) { return s ? "\"" + *s + "\"" : std::string("(unnamed)"); }

Error raw_error(const char* fn, const Raw& raw, const FrameRef& A, const FrameRef& B, Time t) {
  const char* arg = raw.which == 0 ? "A" : "B";
  const FrameRef& f = raw.which == 0 ? A : B;
  std::string fname = std::string(fn) + "(): ";
  switch (raw.code) {
    case Code::kEmpty:
      return make_error(ErrorCode::kInvalidArgument,
                        fname + "invalid argument passed as frame " + arg +
                            (f.kind() == FrameRef::Kind::kName ? ": frame names cannot be empty"
                                                               : ": the null frame"));
    case Code::kNotFound:
      return make_error(ErrorCode::kNotFound, fname + f.describe() + " passed to " + fn +
                                                  "() as frame " + arg +
                                                  " does not exist in the frame tree");
    case Code::kNotConnected:
      return make_error(ErrorCode::kNotConnected,
                        fname + "Could not find a connection between " + quoted(raw.name_a) +
                            " and " + quoted(raw.name_b) +
                            " because they are not part of the same tree (their roots are " +
                            quoted(raw.root_a) + " and " + quoted(raw.root_b) + ")");
    case Code::kPast:
    case Code::kFuture:
      return make_error(ErrorCode::kExtrapolation,
                        fname + "Lookup would require extrapolation into the " +
                            (raw.code == Code::kPast ? "past" : "future") + ". Requested time " +
                            std::to_string(t) + " but the " +
                            (raw.code == Code::kPast ? "earliest" : "latest") +
                            " data is at time " + std::to_string(raw.bound) +
                            ", when looking up transform from frame " + quoted(raw.name_b) +
                            " to frame " + quoted(raw.name_a) + " (on the edge " +
                            quoted(raw.edge_parent) + " -> " + quoted(raw.edge_child) + ")");
    case Code::kNoParent:
      return make_error(ErrorCode::kNotConnected, fname + f.describe() + " has no RT parent");
    case Code::kTorn:
    case Code::kOk:
      break;
  }
  return make_error(ErrorCode::kInternal, fname + "inconsistent frame table");
}

}  // namespace

std::string FrameRef::describe() const {
  switch (kind_) {
    case Kind::kName:
      return "\"" + std::string(name_) + "\"";
    case Kind::kId:
      return "node " + id_.to_string();
    case Kind::kHandle:
      return "frame #" + std::to_string(frame_.slot) + "/" + std::to_string(frame_.generation);
  }
  return "?";
}

// ------------------------------------------------------------------------------------ FrameReader

FrameReader::FrameReader(std::shared_ptr<Core> core, bool registered) : core_(std::move(core)) {
  if (!registered) return;
  reader_index_ = core_->register_reader();
  if (reader_index_ < 0)
    throw std::length_error("FrameTree::reader(): all " + std::to_string(internal::kMaxReaders) +
                            " reader slots are taken");
}

FrameReader::FrameReader(FrameReader&& o) noexcept
    : core_(std::move(o.core_)), reader_index_(o.reader_index_), announced_(o.announced_) {
  o.reader_index_ = -1;
}

FrameReader& FrameReader::operator=(FrameReader&& o) noexcept {
  if (this == &o) return *this;
  if (core_ && reader_index_ >= 0) core_->unregister_reader(reader_index_);
  core_ = std::move(o.core_);
  reader_index_ = o.reader_index_;
  announced_ = o.announced_;
  o.reader_index_ = -1;
  return *this;
}

FrameReader::~FrameReader() {
  if (core_ && reader_index_ >= 0) core_->unregister_reader(reader_index_);
}

void FrameReader::enter() {
  if (reader_index_ < 0) return;  // the owner's own reader: nothing is freed while it reads
  auto& slot = core_->readers[reader_index_].announced;
  if (announced_ == 0) {
    // Coming online: make the announcement visible before reading anything (pairs with the
    // seq_cst fence in Core::reclaim), then announce the epoch seen after it.
    slot.store(core_->epoch.load(std::memory_order_seq_cst), std::memory_order_seq_cst);
    std::atomic_thread_fence(std::memory_order_seq_cst);
    announced_ = core_->epoch.load(std::memory_order_seq_cst);
    slot.store(announced_, std::memory_order_release);
    return;
  }
  const std::uint64_t e = core_->epoch.load(std::memory_order_acquire);
  if (e != announced_) {
    announced_ = e;
    slot.store(e, std::memory_order_release);
  }
}

void FrameReader::idle() {
  if (reader_index_ < 0) return;
  announced_ = 0;
  core_->readers[reader_index_].announced.store(0, std::memory_order_release);
}

std::uint64_t FrameReader::version() const {
  return core_->seq.load(std::memory_order_acquire) / 2;
}

template <class T, class Read>
Result<T> FrameReader::read_frame(const char* fn, const FrameRef& f, Read&& read) {
  enter();
  struct Out {
    Code code;
    T value;
  };
  const Out out = internal::latch_read(*core_, [&](int c) {
    Out o{Code::kOk, T{}};
    std::uint32_t s = 0;
    o.code = resolve(*core_, c, f, &s);
    if (o.code == Code::kOk) o.code = read(c, s, o.value);
    return o;
  });
  if (out.code != Code::kOk) {
    Raw raw;
    raw.code = out.code;
    return raw_error(fn, raw, f, f, 0);
  }
  return out.value;
}

Result<Frame> FrameReader::frame(FrameRef f) {
  return read_frame<Frame>("frame", f, [&](int c, std::uint32_t s, Frame& out) {
    out = Frame{s, ld(core_->slot(c, s)->generation)};
    return Code::kOk;
  });
}

Result<NodeId> FrameReader::node(FrameRef f) {
  return read_frame<NodeId>("node", f, [&](int c, std::uint32_t s, NodeId& id) {
    const SlotData* d = core_->slot(c, s);
    id.dot.replica.agent = ld(d->id[0]);
    id.dot.replica.incarnation = ld(d->id[1]);
    id.dot.counter = ld(d->id[2]);
    return Code::kOk;
  });
}

Result<std::string> FrameReader::name(FrameRef f) {
  auto n = read_frame<const std::string*>("name", f,
                                          [&](int c, std::uint32_t s, const std::string*& out) {
                                            out = load_name(core_->slot(c, s));
                                            return Code::kOk;
                                          });
  if (!n.ok()) return n.error();
  return *n ? **n : std::string();
}

Result<Eigen::Isometry3d> FrameReader::lookup(FrameRef A, FrameRef B) {
  enter();
  Raw raw;
  internal::latch_run(*core_, [&](int c) { read_latest(*core_, c, A, B, raw); });
  if (raw.code != Code::kOk) return raw_error("lookup", raw, A, B, 0);
  return internal::to_isometry(raw.R, raw.p);
}

Result<Eigen::Isometry3d> FrameReader::lookup_at(FrameRef A, FrameRef B, Time t) {
  enter();
  Raw raw;
  internal::latch_run(*core_, [&](int c) {
    read_at(*core_, c, A, B, t, raw);
    if (raw.code == Code::kPast || raw.code == Code::kFuture) {
      raw.name_a = load_name(core_->slot(c, raw.sa));
      raw.name_b = load_name(core_->slot(c, raw.sb));
    }
  });
  if (raw.code != Code::kOk) return raw_error("lookup_at", raw, A, B, t);
  return internal::to_isometry(raw.R, raw.p);
}

Result<Eigen::Vector3d> FrameReader::transform_point(FrameRef A, FrameRef B,
                                                     const Eigen::Vector3d& p_BoQ_B,
                                                     std::optional<Time> t) {
  auto X_AB = t ? lookup_at(A, B, *t) : lookup(A, B);
  if (!X_AB.ok()) return X_AB.error();
  return Eigen::Vector3d(*X_AB * p_BoQ_B);
}

Result<Eigen::Isometry3d> FrameReader::transform_pose(FrameRef A, FrameRef B,
                                                      const Eigen::Isometry3d& X_BC,
                                                      std::optional<Time> t) {
  auto X_AB = t ? lookup_at(A, B, *t) : lookup(A, B);
  if (!X_AB.ok()) return X_AB.error();
  return Eigen::Isometry3d(*X_AB * X_BC);
}

Result<std::pair<Frame, Eigen::Isometry3d>> FrameReader::root_pose(FrameRef F) {
  struct RootPose {
    Frame root;
    double R[9];
    double p[3];
  };
  auto X = read_frame<RootPose>("root_pose", F, [&](int c, std::uint32_t s, RootPose& out) {
    const SlotData* d = core_->slot(c, s);
    const std::int32_t r = ld(d->root);
    const SlotData* rd = r >= 0 ? core_->slot(c, static_cast<std::uint32_t>(r)) : nullptr;
    if (rd == nullptr) return Code::kTorn;
    out.root = Frame{static_cast<std::uint32_t>(r), ld(rd->generation)};
    load_root_pose(d, out.R, out.p);
    return Code::kOk;
  });
  if (!X.ok()) return X.error();
  return std::make_pair(X->root, internal::to_isometry(X->R, X->p));
}

Result<std::uint64_t> FrameReader::pose_version(FrameRef F) {
  return read_frame<std::uint64_t>("pose_version", F,
                                   [&](int c, std::uint32_t s, std::uint64_t& v) {
                                     v = ld(core_->slot(c, s)->version);
                                     return Code::kOk;
                                   });
}

Result<std::pair<Time, Time>> FrameReader::edge_time_range(FrameRef F) {
  return read_frame<std::pair<Time, Time>>(
      "edge_time_range", F, [&](int c, std::uint32_t s, std::pair<Time, Time>& range) {
        const SlotData* d = core_->slot(c, s);
        if (ld(d->parent) < 0) return Code::kNoParent;
        const HistoryBlock* h = d->history.load(std::memory_order_acquire);
        const std::uint32_t n = history_size(h);
        if (n < 2)
          range = {ld(d->stamp), std::numeric_limits<Time>::max()};
        else
          range = {ld(h->samples()[0].stamp), ld(h->samples()[n - 1].stamp)};
        return Code::kOk;
      });
}

// ------------------------------------------------------------------------------------ owner

namespace {

struct Sample {
  Time stamp;
  QP X;
};

/// Exact equality, number by number (==, as std::equal: -0 equals +0).
bool same_values(const QP& a, const QP& b) {
  return std::equal(a.q, a.q + 4, b.q) && std::equal(a.p, a.p + 3, b.p);
}
bool same_values(const Sample& a, const Sample& b) {
  return a.stamp == b.stamp && same_values(a.X, b.X);
}

/// The owner's copy of one frame.
struct Node {
  NodeId id;
  bool live = false;
  std::uint32_t generation = 1;
  std::string name;  // effective name
  std::int32_t parent = kNone;
  std::vector<std::int32_t> children;
  QP X_PN;
  Time stamp = 0;
  std::vector<Sample> samples;  // current epoch, ascending, distinct stamps (published if >= 2)
  // Root-pose cache.
  double R_RN[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  double p_RN[3] = {0, 0, 0};
  std::int32_t root = kNone;
  std::uint32_t depth = 0;
  std::uint64_t version = 0;
  // Bookkeeping.
  bool world_dirty = false;
  bool touched = false;  // to publish
  bool hist_dirty = false;
  const std::string* pub_name = nullptr;
  HistoryBlock* pub_hist[2] = {nullptr, nullptr};
};

struct TableOp {
  bool insert;
  std::uint64_t hash;
  std::uint32_t slot;
};

/// The owner's bookkeeping of one published key table (both copies are identical).
struct TableState {
  std::uint32_t capacity = 0;
  std::uint32_t used = 0;  // non-empty entries (live and tombstones)
  std::uint32_t live = 0;
  std::vector<TableOp> ops;
  bool rebuild = true;
};

/// Base of a stored name ("mug" for "mug~0000...").
std::string base_name(const std::string& effective) {
  auto t = effective.find('~');
  return t == std::string::npos ? effective : effective.substr(0, t);
}

/// The samples lookups interpolate: the current epoch's history plus the current pose, at most
/// one per stamp (the greatest by (stamp, dot), as the graph orders them).
void build_samples(const graph::RtEdge& e, std::span<const graph::RtSample> hist,
                   std::vector<Sample>& out) {
  out.clear();
  for (const graph::RtSample& s : hist) {
    if (!(s.epoch == e.epoch)) continue;
    Sample x{s.stamp, internal::from_pose(s.pose)};
    if (!out.empty() && out.back().stamp == s.stamp)
      out.back() = x;  // ascending: the later wins
    else
      out.push_back(x);
  }
  // The current pose is the greatest sample of its epoch (or the move's own pose).
  Sample cur{e.stamp, internal::from_pose(e.pose)};
  auto it = std::lower_bound(out.begin(), out.end(), e.stamp,
                             [](const Sample& s, Time t) { return s.stamp < t; });
  if (it != out.end() && it->stamp == e.stamp)
    *it = cur;
  else
    out.insert(it, cur);
}

}  // namespace

struct FrameTree::Owner {
  std::vector<Node> nodes;
  std::vector<std::int32_t> free_slots;
  std::unordered_map<NodeId, std::int32_t> by_id;
  std::unordered_map<std::string, std::int32_t> by_name;
  TableState names, ids;
  std::vector<std::int32_t> touched;  // slots to publish
  std::vector<std::int32_t> world_dirty_roots;
  std::vector<Frame> moved;
  std::vector<NodeId> removed;
  std::vector<std::pair<std::uint64_t, Listener>> listeners;
  std::vector<std::pair<std::uint64_t, Listener>> notifying;  // notify()'s snapshot buffer
  std::uint64_t next_listener = 1;
  std::uint64_t audit_cursor = 0;
  std::size_t audit_per_batch = 0;
  Stats stats;
  // The Updater's working buffers, kept between batches (cleared, not freed).
  std::vector<NodeId> rt_dirty;
  std::unordered_set<NodeId> rt_seen;
  std::vector<std::int32_t> marked, stack, path;
  std::vector<Sample> samples;

  void touch(std::int32_t s) {
    if (!nodes[s].touched) {
      nodes[s].touched = true;
      touched.push_back(s);
    }
  }

  /// Calls every listener. A callback may add or remove listeners, or cause a nested update:
  /// the listeners registered now are called, from a snapshot (in a reused buffer; a nested call
  /// finds it taken and makes its own).
  void notify(const FrameUpdate& u) {
    if (listeners.empty()) return;
    std::vector<std::pair<std::uint64_t, Listener>> snapshot;
    snapshot.swap(notifying);
    snapshot.assign(listeners.begin(), listeners.end());
    for (auto& [id, l] : snapshot) l(u);
    snapshot.clear();
    notifying.swap(snapshot);
  }
};

FrameTree::FrameTree(graph::Graph& g, FrameTreeOptions options)
    : g_(&g),
      core_(std::make_shared<Core>()),
      own_(std::make_unique<Owner>()),
      self_(core_, false) {
  own_->audit_per_batch = options.audit_per_batch;
  sync();
  if (options.follow) {
    followed_ = &g;
    sub_ = g.subscribe([this](const graph::ChangeBatch& b) { on_batch(b); });
  }
}

FrameTree::FrameTree(const graph::Graph& g)
    : g_(&g),
      core_(std::make_shared<Core>()),
      own_(std::make_unique<Owner>()),
      self_(core_, false) {
  sync();
}

FrameTree::~FrameTree() {
  if (sub_) followed_->unsubscribe(*sub_);
}

FrameReader FrameTree::reader() { return FrameReader(core_, true); }

std::uint64_t FrameTree::add_listener(Listener l) {
  std::uint64_t id = own_->next_listener++;
  own_->listeners.emplace_back(id, std::move(l));
  return id;
}

void FrameTree::remove_listener(std::uint64_t id) {
  auto& v = own_->listeners;
  v.erase(std::remove_if(v.begin(), v.end(), [&](const auto& p) { return p.first == id; }),
          v.end());
}

Frame FrameTree::frame_of(NodeId id) const {
  auto it = own_->by_id.find(id);
  if (it == own_->by_id.end()) return Frame{};
  const Node& n = own_->nodes[it->second];
  return Frame{static_cast<std::uint32_t>(it->second), n.generation};
}

namespace {
const Node* live_node(const std::vector<Node>& nodes, Frame f) {
  if (f.is_null() || f.slot >= nodes.size()) return nullptr;
  const Node& n = nodes[f.slot];
  return n.live && n.generation == f.generation ? &n : nullptr;
}
}  // namespace

std::optional<Eigen::Isometry3d> FrameTree::root_pose_of(Frame f) const {
  const Node* n = live_node(own_->nodes, f);
  if (n == nullptr) return std::nullopt;
  return internal::to_isometry(n->R_RN, n->p_RN);
}

Frame FrameTree::root_of(Frame f) const {
  const Node* n = live_node(own_->nodes, f);
  if (n == nullptr || n->root < 0) return Frame{};
  return Frame{static_cast<std::uint32_t>(n->root), own_->nodes[n->root].generation};
}

NodeId FrameTree::node_of(Frame f) const {
  const Node* n = live_node(own_->nodes, f);
  return n ? n->id : NodeId{};
}

FrameTree::Stats FrameTree::stats() const {
  Stats s = own_->stats;
  s.frames = own_->by_id.size();
  s.retired_pending = core_->retired.size();
  return s;
}

namespace {

/// Owner-side operations on the master copy; kept out of the class to keep the header small.
class Updater {
 public:
  Updater(const graph::Graph& g, FrameTree::Owner& o) : g_(g), o_(o), rt_dirty_(o.rt_dirty) {
    rt_dirty_.clear();
  }

  std::int32_t slot_of(const NodeId& id) const {
    auto it = o_.by_id.find(id);
    return it == o_.by_id.end() ? kNone : it->second;
  }

  /// The slot of a visible node, allocated on first sight.
  std::int32_t ensure(const NodeId& id) {
    std::int32_t s = slot_of(id);
    if (s != kNone) return s;
    if (!o_.free_slots.empty()) {
      s = o_.free_slots.back();
      o_.free_slots.pop_back();
    } else {
      if (o_.nodes.size() >= internal::kMaxSlots)
        throw std::length_error("FrameTree: too many frames");
      s = static_cast<std::int32_t>(o_.nodes.size());
      o_.nodes.emplace_back();
    }
    Node& n = o_.nodes[s];
    n.id = id;
    n.live = true;
    n.parent = kNone;
    n.children.clear();
    n.X_PN = QP{};
    n.stamp = 0;
    n.samples.clear();
    n.hist_dirty = true;
    n.world_dirty = false;
    n.root = kNone;  // forces a version bump on first computation
    o_.by_id.emplace(id, s);
    o_.ids.ops.push_back(TableOp{true, hash_id(id), static_cast<std::uint32_t>(s)});
    ++o_.ids.live;
    names_to_refresh_.insert(base_name(g_.name_of(id)));
    mark_world(s);
    o_.touch(s);
    return s;
  }

  void remove(std::int32_t s) {
    Node& n = o_.nodes[s];
    if (!n.live) return;
    unlink(s);
    for (std::int32_t c : n.children) {
      o_.nodes[c].parent = kNone;
      rt_dirty_.push_back(o_.nodes[c].id);
      mark_world(c);
    }
    n.children.clear();
    names_to_refresh_.insert(base_name(n.name));
    set_name(s, std::string());
    o_.ids.ops.push_back(TableOp{false, hash_id(n.id), static_cast<std::uint32_t>(s)});
    --o_.ids.live;
    o_.by_id.erase(n.id);
    o_.removed.push_back(n.id);
    n.live = false;
    ++n.generation;
    if (n.generation == 0) n.generation = 1;
    n.samples.clear();
    n.hist_dirty = true;
    n.world_dirty = false;
    o_.touch(s);
    o_.free_slots.push_back(s);
  }

  void note_rt_change(const NodeId& child) { rt_dirty_.push_back(child); }

  /// Does the owner's copy of frame `s` differ from the graph (its edge or samples)? Names are
  /// kept by the create / delete events of their namesakes.
  bool differs(std::int32_t s) {
    const Node& n = o_.nodes[s];
    if (!g_.has_node(n.id)) return true;
    const auto e = g_.rt_edge(n.id);  // none exactly when the node has no parent
    const std::int32_t ps = e ? slot_of(e->parent) : kNone;
    if (ps != n.parent || (e && ps == kNone)) return true;
    if (!e) return !n.samples.empty() || n.stamp != 0;
    const QP X = internal::from_pose(e->pose);
    if (e->stamp != n.stamp || !same_values(X, n.X_PN)) return true;
    std::vector<Sample>& want = o_.samples;
    build_samples(*e, g_.rt_history(n.id), want);
    if (want.size() != n.samples.size()) return true;
    for (std::size_t i = 0; i < want.size(); ++i)
      if (!same_values(want[i], n.samples[i])) return true;
    return false;
  }

  /// Compares up to `count` live frames with the graph, round robin, and queues repairs.
  std::size_t audit(std::size_t count) {
    std::size_t repaired = 0;
    const std::size_t total = o_.nodes.size();
    for (std::size_t seen = 0; seen < total && count > 0; ++seen) {
      const std::int32_t s = static_cast<std::int32_t>(o_.audit_cursor++ % total);
      const Node& n = o_.nodes[s];
      if (!n.live) continue;
      --count;
      if (!differs(s)) continue;
      ++repaired;
      if (!g_.has_node(n.id)) {
        remove(s);
        continue;
      }
      rt_dirty_.push_back(n.id);
      names_to_refresh_.insert(base_name(g_.name_of(n.id)));
      names_to_refresh_.insert(base_name(n.name));
    }
    return repaired;
  }
  void note_name(const std::string& base) { names_to_refresh_.insert(base); }

  /// Re-reads a child's RT edge from the graph.
  void refresh_edge(const NodeId& id) {
    if (!g_.has_node(id)) return;
    std::int32_t s = ensure(id);
    const auto e = g_.rt_edge(id);  // none exactly when the node has no parent
    std::int32_t ps = e ? ensure(e->parent) : kNone;
    Node& n = o_.nodes[s];
    if (ps != n.parent) {
      unlink(s);
      n.parent = ps;
      if (ps != kNone) o_.nodes[ps].children.push_back(s);
    }
    if (ps != kNone) {
      n.X_PN = internal::from_pose(e->pose);
      n.stamp = e->stamp;
      build_samples(*e, g_.rt_history(id), n.samples);
    } else {
      n.X_PN = QP{};
      n.stamp = 0;
      n.samples.clear();
    }
    n.hist_dirty = true;
    o_.touch(s);
    mark_world(s);
  }

  /// Applies queued edge and name refreshes, then recomputes the dirty root poses.
  void finish() {
    // Each queued child once, in queue order (refresh_edge() queues nothing more).
    std::unordered_set<NodeId>& seen = o_.rt_seen;
    seen.clear();
    for (const NodeId& id : rt_dirty_)
      if (seen.insert(id).second) refresh_edge(id);
    rt_dirty_.clear();
    refresh_names();
    recompute_world();
  }

 private:
  void unlink(std::int32_t s) {
    Node& n = o_.nodes[s];
    if (n.parent == kNone) return;
    auto& sib = o_.nodes[n.parent].children;
    auto it = std::find(sib.begin(), sib.end(), s);
    if (it != sib.end()) {
      *it = sib.back();
      sib.pop_back();
    }
    n.parent = kNone;
  }

  void mark_world(std::int32_t s) { o_.world_dirty_roots.push_back(s); }

  void set_name(std::int32_t s, std::string name) {
    Node& n = o_.nodes[s];
    if (name == n.name && n.live) return;
    if (!n.name.empty()) {
      auto it = o_.by_name.find(n.name);
      if (it != o_.by_name.end() && it->second == s) {
        o_.by_name.erase(it);
        o_.names.ops.push_back(TableOp{false, hash_name(n.name), static_cast<std::uint32_t>(s)});
        --o_.names.live;
      }
    }
    n.name = std::move(name);
    o_.touch(s);
  }

  void refresh_names() {
    // Two passes: drop stale names first, so that swapped names never collide.
    std::vector<std::pair<std::int32_t, std::string>> want;
    for (const std::string& base : names_to_refresh_) {
      if (base.empty()) continue;
      for (const NodeId& id : g_.namesakes(base)) {
        std::int32_t s = slot_of(id);
        if (s == kNone) continue;
        std::string eff = g_.name_of(id);
        if (eff != o_.nodes[s].name) {
          set_name(s, std::string());
          want.emplace_back(s, std::move(eff));
        }
      }
    }
    for (auto& [s, eff] : want) {
      Node& n = o_.nodes[s];
      n.name = eff;
      auto [it, fresh] = o_.by_name.emplace(eff, s);
      if (!fresh) {
        // Another slot still holds this name (it will be refreshed too): take it over.
        o_.names.ops.push_back(
            TableOp{false, hash_name(eff), static_cast<std::uint32_t>(it->second)});
        o_.nodes[it->second].name.clear();
        o_.touch(it->second);
        it->second = s;
        --o_.names.live;
      }
      o_.names.ops.push_back(TableOp{true, hash_name(eff), static_cast<std::uint32_t>(s)});
      ++o_.names.live;
    }
    names_to_refresh_.clear();
  }

  void recompute_world() {
    auto& nodes = o_.nodes;
    // Mark every live node under a dirty root (a node already marked has its subtree marked).
    std::vector<std::int32_t>& marked = o_.marked;
    std::vector<std::int32_t>& stack = o_.stack;
    marked.clear();
    stack.clear();
    for (std::int32_t r : o_.world_dirty_roots) {
      if (!nodes[r].live || nodes[r].world_dirty) continue;
      stack.push_back(r);
      while (!stack.empty()) {
        std::int32_t s = stack.back();
        stack.pop_back();
        Node& n = nodes[s];
        if (n.world_dirty) continue;
        n.world_dirty = true;
        marked.push_back(s);
        for (std::int32_t c : n.children) stack.push_back(c);
      }
    }
    o_.world_dirty_roots.clear();
    // Compute each marked node after its parent.
    std::vector<std::int32_t>& path = o_.path;
    for (std::int32_t s : marked) {
      path.clear();
      for (std::int32_t x = s; x != kNone && nodes[x].world_dirty; x = nodes[x].parent)
        path.push_back(x);
      for (auto it = path.rbegin(); it != path.rend(); ++it) compute(*it);
    }
    o_.stats.pose_recomputes += marked.size();
  }

  void compute(std::int32_t s) {
    Node& n = o_.nodes[s];
    double R[9], p[3];
    std::int32_t root;
    std::uint32_t depth;
    if (n.parent == kNone) {
      static constexpr double I[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
      std::copy(I, I + 9, R);
      p[0] = p[1] = p[2] = 0.0;
      root = s;
      depth = 0;
    } else {
      const Node& par = o_.nodes[n.parent];
      double R_PN[9];
      internal::quat_to_matrix(n.X_PN.q, R_PN);
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j)
          R[i * 3 + j] = par.R_RN[i * 3 + 0] * R_PN[0 * 3 + j] +
                         par.R_RN[i * 3 + 1] * R_PN[1 * 3 + j] +
                         par.R_RN[i * 3 + 2] * R_PN[2 * 3 + j];
        p[i] = par.R_RN[i * 3 + 0] * n.X_PN.p[0] + par.R_RN[i * 3 + 1] * n.X_PN.p[1] +
               par.R_RN[i * 3 + 2] * n.X_PN.p[2] + par.p_RN[i];
      }
      root = par.root;
      depth = par.depth + 1;
    }
    bool changed = root != n.root || depth != n.depth || !std::equal(R, R + 9, n.R_RN) ||
                   !std::equal(p, p + 3, n.p_RN);
    n.world_dirty = false;
    if (!changed) return;
    std::copy(R, R + 9, n.R_RN);
    std::copy(p, p + 3, n.p_RN);
    n.root = root;
    n.depth = depth;
    ++n.version;
    o_.touch(s);
    o_.moved.push_back(Frame{static_cast<std::uint32_t>(s), n.generation});
  }

  const graph::Graph& g_;
  FrameTree::Owner& o_;
  std::vector<NodeId>& rt_dirty_;  // o_.rt_dirty
  std::unordered_set<std::string> names_to_refresh_;
};

// ---- publishing

void fill_history(HistoryBlock* h, const std::vector<Sample>& samples) {
  const std::uint32_t n = static_cast<std::uint32_t>(samples.size());
  for (std::uint32_t i = 0; i < n; ++i) {
    HistSample& d = h->samples()[i];
    const Sample& a = samples[i];
    st(d.stamp, a.stamp);
    for (int k = 0; k < 4; ++k) st(d.X[k], a.X.q[k]);
    for (int k = 0; k < 3; ++k) st(d.X[4 + k], a.X.p[k]);
    double theta = 0, cos_theta = 1, inv_sin = 0, sign = 1, inv_dt = 0;
    if (i + 1 < n) {
      const Sample& b = samples[i + 1];
      const double dot =
          a.X.q[0] * b.X.q[0] + a.X.q[1] * b.X.q[1] + a.X.q[2] * b.X.q[2] + a.X.q[3] * b.X.q[3];
      sign = dot < 0 ? -1.0 : 1.0;
      const double ad = std::fabs(dot);
      if (ad < 1.0 - 1e-12) {  // otherwise blend linearly, as Eigen's slerp does
        theta = std::acos(ad);
        inv_sin = 1.0 / std::sin(theta);
        cos_theta = ad;
      }
      inv_dt = 1.0 / static_cast<double>(b.stamp - a.stamp);
    }
    st(d.theta, theta);
    st(d.cos_theta, cos_theta);
    st(d.inv_sin, inv_sin);
    st(d.sign, sign);
    st(d.inv_dt, inv_dt);
  }
  st(h->size, n);
}

void write_slot(SlotData* d, Node& n, int copy, std::vector<HistoryBlock*>& retire_blocks) {
  st(d->generation, n.generation);
  st(d->live, n.live ? 1u : 0u);
  st(d->parent, n.parent);
  st(d->root, n.root);
  st(d->depth, n.depth);
  st(d->version, n.version);
  st(d->id[0], n.id.dot.replica.agent);
  st(d->id[1], n.id.dot.replica.incarnation);
  st(d->id[2], n.id.dot.counter);
  d->name.store(n.pub_name, std::memory_order_release);  // the string is complete before
  for (int i = 0; i < 9; ++i) st(d->X_RN[i], n.R_RN[i]);
  for (int i = 0; i < 3; ++i) st(d->X_RN[9 + i], n.p_RN[i]);
  for (int i = 0; i < 4; ++i) st(d->X_PN[i], n.X_PN.q[i]);
  for (int i = 0; i < 3; ++i) st(d->X_PN[4 + i], n.X_PN.p[i]);
  st(d->stamp, n.stamp);
  if (n.hist_dirty) {
    HistoryBlock*& h = n.pub_hist[copy];
    const std::size_t need = n.live && n.samples.size() >= 2 ? n.samples.size() : 0;
    if (need == 0) {
      if (h) st(h->size, 0u);
    } else {
      if (h == nullptr || h->capacity < need) {
        const auto cap = static_cast<std::uint32_t>(std::max<std::size_t>(4, std::bit_ceil(need)));
        if (h) retire_blocks.push_back(h);
        h = HistoryBlock::create(cap);
      }
      fill_history(h, n.samples);
    }
    d->history.store(h, std::memory_order_release);  // a new block is complete before
  }
}

void apply_ops(KeyTable* t, const std::vector<TableOp>& ops, TableState* count) {
  for (const TableOp& op : ops) {
    std::uint32_t i = static_cast<std::uint32_t>(op.hash) & t->mask;
    if (op.insert) {
      for (;; i = (i + 1) & t->mask) {
        const std::uint64_t e = ld(t->entries[i]);
        if (e == KeyTable::kEmpty || e == KeyTable::kTomb) {
          if (e == KeyTable::kEmpty && count) ++count->used;
          st(t->entries[i], KeyTable::pack(op.hash, op.slot));
          break;
        }
      }
    } else {
      const std::uint64_t want = KeyTable::pack(op.hash, op.slot);
      for (std::uint32_t n = 0; n <= t->mask; ++n, i = (i + 1) & t->mask) {
        const std::uint64_t e = ld(t->entries[i]);
        if (e == KeyTable::kEmpty) break;
        if (e == want) {
          st(t->entries[i], KeyTable::kTomb);
          break;
        }
      }
    }
  }
}

KeyTable* build_table(std::uint32_t cap,
                      const std::vector<std::pair<std::uint64_t, std::uint32_t>>& entries) {
  auto* t = new KeyTable(cap);
  std::vector<TableOp> ops;
  ops.reserve(entries.size());
  for (const auto& [h, s] : entries) ops.push_back(TableOp{true, h, s});
  apply_ops(t, ops, nullptr);
  return t;
}

}  // namespace

void FrameTree::sync() {
  Owner& o = *own_;
  Updater up(*g_, o);
  // Forget frames whose nodes are gone, then (re)read every visible node's edge.
  std::vector<std::int32_t> gone;
  for (const auto& [id, s] : o.by_id)
    if (!g_->has_node(id)) gone.push_back(s);
  for (std::int32_t s : gone) up.remove(s);
  for (const NodeId& id : g_->nodes()) {
    up.ensure(id);
    up.note_rt_change(id);
    up.note_name(base_name(g_->name_of(id)));
  }
  // Re-derive names from scratch.
  for (auto& n : o.nodes)
    if (n.live) n.name.clear();
  o.by_name.clear();
  o.names.live = 0;
  o.names.rebuild = true;
  o.names.ops.clear();
  up.finish();
  ++o.stats.resyncs;
  // Everything may have changed: publish every live slot.
  for (std::size_t s = 0; s < o.nodes.size(); ++s)
    if (o.nodes[s].live) o.touch(static_cast<std::int32_t>(s));
  FrameUpdate u;
  u.resynced = true;
  publish(u);
}

void FrameTree::on_batch(const graph::ChangeBatch& b) {
  Owner& o = *own_;
  Updater up(*g_, o);
  bool any = false;
  for (const graph::NodeChange& nc : b.nodes) {
    if (nc.kind == graph::ChangeKind::kCreated) {
      if (g_->has_node(nc.id)) {
        up.ensure(nc.id);
        up.note_rt_change(nc.id);
        any = true;
      }
    } else if (nc.kind == graph::ChangeKind::kDeleted) {
      std::int32_t s = up.slot_of(nc.id);
      if (s != kNone) {
        up.remove(s);
        any = true;
      }
    }
  }
  for (const graph::EdgeChange& ec : b.edges) {
    if (ec.key.type != graph::symbols::rt()) continue;
    up.note_rt_change(ec.key.to);
    any = true;
  }
  if (any) up.finish();
  if (o.audit_per_batch > 0) {
    const std::size_t repaired = up.audit(o.audit_per_batch);
    o.stats.repairs += repaired;
    if (repaired > 0) {
      up.finish();
      any = true;
    }
  }
  FrameUpdate u;
  u.batch = &b;
  if (any)
    publish(u);
  else
    o.notify(u);
}

void FrameTree::publish(FrameUpdate& u) {
  Owner& o = *own_;
  Core& core = *core_;
  // Chunks for new slots (published before the slots are referenced).
  const std::uint32_t need_chunks = static_cast<std::uint32_t>(
      (o.nodes.size() + internal::kChunkSlots - 1) / internal::kChunkSlots);
  while (core.chunk_count < need_chunks) {
    core.chunks[core.chunk_count].store(new internal::Chunk(), std::memory_order_release);
    ++core.chunk_count;
  }
  // Name strings: one immutable string per published name.
  std::vector<const std::string*> retire_strings;
  for (std::int32_t s : o.touched) {
    Node& n = o.nodes[s];
    const std::string_view want = n.live ? std::string_view(n.name) : std::string_view();
    const std::string* cur = n.pub_name;
    if (cur && *cur == want) continue;
    if (cur == nullptr && want.empty()) continue;
    if (cur) retire_strings.push_back(cur);
    n.pub_name = want.empty() ? nullptr : new std::string(want);
  }
  // Key tables: rebuild when due, else replay the operations on both copies.
  auto plan = [](TableState& ts) {
    std::uint32_t inserts = 0;
    for (const TableOp& op : ts.ops) inserts += op.insert ? 1 : 0;
    if (ts.rebuild || ts.capacity == 0 || 2ull * (ts.used + inserts) > ts.capacity) {
      ts.rebuild = true;
      ts.capacity = pow2_at_least(4ull * ts.live + 16);
      ts.used = ts.live;
    }
  };
  plan(o.names);
  plan(o.ids);
  std::vector<std::pair<std::uint64_t, std::uint32_t>> name_entries, id_entries;
  if (o.names.rebuild)
    for (const auto& [name, s] : o.by_name)
      name_entries.emplace_back(hash_name(name), static_cast<std::uint32_t>(s));
  if (o.ids.rebuild)
    for (const auto& [id, s] : o.by_id)
      id_entries.emplace_back(hash_id(id), static_cast<std::uint32_t>(s));
  std::vector<KeyTable*> retire_tables;
  std::vector<HistoryBlock*> retire_blocks;

  for (int copy = 0; copy < 2; ++copy) {
    // Readers move to the other copy; from here on this copy may be modified.
    core.seq.store(core.seq.load(std::memory_order_relaxed) + 1, std::memory_order_release);
    std::atomic_thread_fence(std::memory_order_release);
    for (auto [ts, ptr, entries] : {std::tuple{&o.names, &core.names[copy], &name_entries},
                                    std::tuple{&o.ids, &core.ids[copy], &id_entries}}) {
      if (ts->rebuild) {
        KeyTable* old = ptr->load(std::memory_order_relaxed);
        if (old) retire_tables.push_back(old);
        ptr->store(build_table(ts->capacity, *entries), std::memory_order_release);
      } else {
        apply_ops(ptr->load(std::memory_order_relaxed), ts->ops, copy == 0 ? ts : nullptr);
      }
    }
    for (std::int32_t s : o.touched)
      write_slot(core.slot(copy, static_cast<std::uint32_t>(s)), o.nodes[s], copy, retire_blocks);
  }
  core.seq.store(core.seq.load(std::memory_order_relaxed), std::memory_order_release);
  for (std::int32_t s : o.touched) {
    o.nodes[s].touched = false;
    o.nodes[s].hist_dirty = false;
  }
  o.touched.clear();
  for (TableState* ts : {&o.names, &o.ids}) {
    ts->ops.clear();
    ts->rebuild = false;
  }
  for (const std::string* p : retire_strings) core.retire(p);
  for (HistoryBlock* p : retire_blocks) core.retire(p);
  for (KeyTable* p : retire_tables) core.retire(p);
  core.reclaim();
  ++o.stats.publishes;

  u.moved = o.moved;
  u.removed = o.removed;
  o.notify(u);
  o.moved.clear();
  o.removed.clear();
}

std::size_t FrameTree::audit(std::size_t frames) {
  Owner& o = *own_;
  Updater up(*g_, o);
  const std::size_t repaired = up.audit(frames);
  o.stats.repairs += repaired;
  if (repaired == 0) return 0;
  up.finish();
  FrameUpdate u;
  publish(u);
  return repaired;
}

std::vector<std::string> FrameTree::check_against_graph() const {
  std::vector<std::string> out;
  const Owner& o = *own_;
  FrameTree fresh(*g_);
  const Owner& f = *fresh.own_;
  if (o.by_id.size() != f.by_id.size())
    out.push_back("frame count " + std::to_string(o.by_id.size()) +
                  " != " + std::to_string(f.by_id.size()));
  for (const auto& [id, s] : f.by_id) {
    auto it = o.by_id.find(id);
    if (it == o.by_id.end()) {
      out.push_back("missing frame for node " + id.to_string());
      continue;
    }
    const Node& a = o.nodes[it->second];
    const Node& b = f.nodes[s];
    std::string who = "frame \"" + b.name + "\": ";
    if (a.name != b.name) out.push_back(who + "name \"" + a.name + "\"");
    NodeId pa = a.parent == kNone ? NodeId{} : o.nodes[a.parent].id;
    NodeId pb = b.parent == kNone ? NodeId{} : f.nodes[b.parent].id;
    if (!(pa == pb)) out.push_back(who + "parent differs");
    if (!std::equal(a.R_RN, a.R_RN + 9, b.R_RN) || !std::equal(a.p_RN, a.p_RN + 3, b.p_RN))
      out.push_back(who + "cached root pose differs");
    if (a.depth != b.depth) out.push_back(who + "depth differs");
    if (o.nodes[a.root].id != f.nodes[b.root].id) out.push_back(who + "root differs");
    if (a.samples.size() != b.samples.size()) {
      out.push_back(who + "sample count " + std::to_string(a.samples.size()) +
                    " != " + std::to_string(b.samples.size()));
    } else {
      for (std::size_t i = 0; i < a.samples.size(); ++i)
        if (!same_values(a.samples[i], b.samples[i]))
          out.push_back(who + "sample " + std::to_string(i) + " differs: stamp " +
                        std::to_string(a.samples[i].stamp) + " vs " +
                        std::to_string(b.samples[i].stamp) + " x " +
                        std::to_string(a.samples[i].X.p[0]) + " vs " +
                        std::to_string(b.samples[i].X.p[0]) + " (of " +
                        std::to_string(a.samples.size()) + ")");
    }
  }
  for (const auto& [name, s] : f.by_name) {
    auto it = o.by_name.find(name);
    if (it == o.by_name.end() || !(o.nodes[it->second].id == f.nodes[s].id))
      out.push_back("name \"" + name + "\" maps elsewhere");
  }
  if (o.by_name.size() != f.by_name.size()) out.push_back("name count differs");
  return out;
}

}  // namespace quiver::kinematics
