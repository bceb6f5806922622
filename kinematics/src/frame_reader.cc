// FrameReader: lock-free lookups for any thread (entering and idling for reclamation, the latch
// around each read), and how a frame reference describes itself.

#include <limits>
#include <stdexcept>

#include "frame_reads.h"
#include "frame_store.h"
#include "pose_math.h"
#include "quiver/kinematics/frames.h"

namespace quiver::kinematics {

using graph::NodeId;
using internal::Code;
using internal::Core;
using internal::HistoryBlock;
using internal::history_size;
using internal::ld;
using internal::load_name;
using internal::load_root_pose;
using internal::Raw;
using internal::raw_error;
using internal::read_at;
using internal::read_latest;
using internal::resolve;
using internal::SlotData;

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

}  // namespace quiver::kinematics
