// Reads of the published frame table under the latch: resolving a frame by name, id or handle,
// selecting and interpolating an edge's samples at a time t, X_AB, and the errors reads report.

#include <algorithm>

#include "frame_keys.h"
#include "frame_reads.h"
#include "frame_store.h"
#include "pose_math.h"

namespace quiver::kinematics {

using graph::NodeId;
using internal::Atom;
using internal::Code;
using internal::Core;
using internal::HistoryBlock;
using internal::HistSample;
using internal::history_size;
using internal::KeyTable;
using internal::ld;
using internal::load_name;
using internal::QP;
using internal::Raw;
using internal::SlotData;

namespace {

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

}  // namespace

namespace internal {

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

}  // namespace internal

namespace {

/// Where one edge's pose at time t comes from: X = slerp/lerp(X0, X1, r) with the interval's
/// precomputed angle data. A constant edge or an exact sample has X0 = X1, r = 0, θ = 0.
struct EdgeSel {
  const Atom<double>* X0;  // qw qx qy qz px py pz
  const Atom<double>* X1;
  double r, theta, cos_theta, inv_sin, sign;
};

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

std::string quoted(const std::string* s) { return s ? "\"" + *s + "\"" : std::string("(unnamed)"); }

}  // namespace

namespace internal {

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

}  // namespace internal
}  // namespace quiver::kinematics
