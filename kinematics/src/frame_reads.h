#pragma once
// Private: reads of the published frame table (a frame resolved, X_AB now or at a time t), what
// one latch attempt finds, and the errors built from it afterwards.

#include <algorithm>
#include <cstdint>
#include <string>

#include "frame_store.h"
#include "quiver/kinematics/frames.h"

namespace quiver::kinematics::internal {

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
inline const std::string* load_name(const SlotData* d) {
  return d->name.load(std::memory_order_acquire);
}

inline void load_root_pose(const SlotData* d, double* R, double* p) {
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

/// How many samples of a (possibly null) published history block may be read.
[[gnu::always_inline]] inline std::uint32_t history_size(const HistoryBlock* h) {
  return h ? std::min(ld(h->size), h->capacity) : 0;
}

/// Resolves a frame reference in copy `c`.
Code resolve(const Core& core, int c, const FrameRef& f, std::uint32_t* slot);

/// Latest-time X_AB in copy c.
void read_latest(const Core& core, int c, const FrameRef& A, const FrameRef& B, Raw& raw);

/// X_AB at time t in copy c: both sides walk up to their lowest common ancestor L, the deeper
/// one alone first, then both in lock step.
void read_at(const Core& core, int c, const FrameRef& A, const FrameRef& B, Time t, Raw& raw);

/// The error a failed read reports, for the function named `fn`.
Error raw_error(const char* fn, const Raw& raw, const FrameRef& A, const FrameRef& B, Time t);

}  // namespace quiver::kinematics::internal
