// The GraphDelta encoder: symbol and replica tables, dot planning, and the ops written in the
// wire format of codec_format.h.

#include <unordered_map>

#include "codec_format.h"
#include "quiver/base/byte_codec.h"
#include "quiver/graph/codec.h"

namespace quiver::graph {
namespace {

using namespace internal;

// A message's tables, kept per thread from one message to the next: encoding a delta like the
// last one allocates nothing. Tables a large state grew are released after it.
struct EncodeTables {
  std::vector<ReplicaId> replicas;
  std::unordered_map<ReplicaId, std::uint64_t> rmap;
  std::vector<Symbol> symbols;
  std::unordered_map<Symbol, std::uint64_t> smap;
};

class Encoder {
 public:
  Encoder(const GraphDelta& d, std::vector<std::uint8_t>& out, std::uint64_t seq_lo, std::uint64_t seq_hi)
      : d_(&d), w_(out), seq_lo_(seq_lo), seq_hi_(seq_hi) {
    replicas_.clear();
    symbols_.clear();
    rmap_.clear();
    smap_.clear();
  }
  ~Encoder() {
    if (replicas_.size() + symbols_.size() > kKeptEntries) tables_ = EncodeTables{};
  }
  Encoder(const Encoder&) = delete;
  Encoder& operator=(const Encoder&) = delete;

  void run() {
    collect_tables();
    plan_dots();
    for (const auto& e : d_->values) fenced_ = fenced_ || e.fence != 0;
    for (const auto& n : d_->nodes) typed_ = typed_ || (!n.has_header && !n.type.is_null());
    header(d_->nodes.size());
    NodeId prev{};
    for (const auto& n : d_->nodes) {
      node(n, prev);
      prev = n.id;
    }
    w_.varint(d_->edges.size());
    for (const auto& e : d_->edges) edge(e);
    if (!d_->rule.empty()) {
      w_.string(d_->rule);
      w_.varint(d_->binding.size());
      for (const auto& [var, id] : d_->binding) {
        w_.string(var);
        node_ref(id);
      }
    }
    if (d_->kind == GraphDelta::Kind::kState) keep(d_->keep);
  }

  // A state from its parts, in three passes over them: the tables, flags and counts; the header
  // and the node ops; the edge ops. Dots are written in full (no implicit run across parts).
  void run_parts(const PartSource& parts) {
    std::size_t nnodes = 0, nedges = 0;
    std::vector<Dot> kept;
    NodeId prev{};
    bool first = true;
    base_ = UINT64_MAX;
    parts(PartOps::kAll, [&](const GraphDelta& p) {
      d_ = &p;
      if (first) {
        add_replica(p.origin);
        p.context.for_each_range([&](const ReplicaId& r, std::uint64_t, std::uint64_t) { add_replica(r); });
        first = false;
      }
      collect_op_tables();
      for_each_added_in_order([&](const Dot& x) {
        if (x.replica == p.origin) base_ = std::min(base_, x.counter);
      });
      for (const auto& e : p.values) fenced_ = fenced_ || e.fence != 0;
      for (const auto& n : p.nodes) {
        typed_ = typed_ || (!n.has_header && !n.type.is_null());
        if (!prev.is_null() && prev.dot.replica == n.id.dot.replica && n.id.dot.counter < prev.dot.counter)
          sorted_ = false;
        prev = n.id;
      }
      nnodes += p.nodes.size();
      nedges += p.edges.size();
      kept.insert(kept.end(), p.keep.begin(), p.keep.end());
    });
    if (base_ == UINT64_MAX) base_ = 0;
    bool started = false;
    prev = NodeId{};
    parts(PartOps::kNodes, [&](const GraphDelta& p) {
      d_ = &p;
      if (!started) header(nnodes);
      started = true;
      for (const auto& n : p.nodes) {
        node(n, prev);
        prev = n.id;
      }
    });
    if (!started) {  // no part at all: an empty state
      GraphDelta empty;
      empty.kind = GraphDelta::Kind::kState;
      d_ = &empty;
      if (replicas_.empty()) add_replica(empty.origin);
      header(0);
    }
    w_.varint(nedges);
    parts(PartOps::kEdges, [&](const GraphDelta& p) {
      d_ = &p;
      for (const auto& e : p.edges) edge(e);
    });
    keep(kept);
  }

 private:
  // Everything before the node ops: magic, kind, flags, tables, context, dot base, node count.
  void header(std::size_t nnodes) {
    w_.u8(kMagic0);
    w_.u8(kMagic1);
    w_.u8(kCodecVersion);
    w_.u8(static_cast<std::uint8_t>(d_->kind));
    const bool seq = seq_lo_ != 0;
    std::uint64_t flags = (implicit_ ? kImplicitDots : 0) | (sorted_ ? kSortedNodes : 0) | (fenced_ ? kFenced : 0) |
                          (d_->rule.empty() ? 0 : kClaim) | (seq ? kSeq : 0) | (typed_ ? kTyped : 0);
    w_.varint(flags);
    if (seq) {
      w_.varint(seq_lo_);
      w_.varint(seq_hi_ - seq_lo_);
    }
    w_.varint(replicas_.size());
    for (const ReplicaId& r : replicas_) {
      w_.fixed64(r.agent);
      w_.varint(r.incarnation);
    }
    w_.varint(symbols_.size());
    for (Symbol s : symbols_) w_.string(s.str());
    std::size_t nranges = d_->context.range_count();
    w_.varint(nranges);
    d_->context.for_each_range([&](const ReplicaId& r, std::uint64_t lo, std::uint64_t hi) {
      w_.varint(rindex(r));
      w_.varint(lo);
      w_.varint(hi - lo);
    });
    if (implicit_) w_.varint(next_implicit_);
    else w_.varint(base_);
    w_.varint(nnodes);
  }

  // Tables are tiny in deltas (one or two replicas, a handful of names): a linear scan with a
  // last-hit cache beats hashing; large states switch to a hash index.
  template <class T, class Map>
  static std::uint64_t find_or_add(std::vector<T>& items, Map& index, std::size_t& last, const T& x, bool add) {
    if (last < items.size() && items[last] == x) return last;
    if (items.size() <= 16 && index.empty()) {
      for (std::size_t i = 0; i < items.size(); ++i)
        if (items[i] == x) return last = i;
      if (!add) return UINT64_MAX;
      items.push_back(x);
      if (items.size() > 16)
        for (std::size_t i = 0; i < items.size(); ++i) index.emplace(items[i], i);
      return last = items.size() - 1;
    }
    if (!add) {
      auto it = index.find(x);
      return it == index.end() ? UINT64_MAX : (last = it->second);
    }
    auto [it, fresh] = index.emplace(x, items.size());
    if (fresh) items.push_back(x);
    return last = it->second;
  }
  std::uint64_t rindex(const ReplicaId& r) { return find_or_add(replicas_, rmap_, rlast_, r, false); }
  void add_replica(const ReplicaId& r) { find_or_add(replicas_, rmap_, rlast_, r, true); }
  void add_symbol(Symbol s) { find_or_add(symbols_, smap_, slast_, s, true); }
  std::uint64_t sindex(Symbol s) { return find_or_add(symbols_, smap_, slast_, s, false); }

  void collect_tables() {
    add_replica(d_->origin);
    d_->context.for_each_range([&](const ReplicaId& r, std::uint64_t, std::uint64_t) { add_replica(r); });
    collect_op_tables();
  }
  // The replicas and symbols of the ops, added dots and keep list.
  void collect_op_tables() {
    // Attribute names by the op that holds them (stream order), whatever order a transaction
    // wrote them in: a decoded delta then re-encodes to the same bytes.
    for (const auto& n : d_->nodes) {
      add_replica(n.id.dot.replica);
      if (n.has_header || !n.type.is_null()) add_symbol(n.type);
      for (std::uint32_t i = n.attrs.begin; i < n.attrs.end; ++i) add_symbol(d_->attrs[i].name);
    }
    for (const auto& e : d_->edges) {
      add_replica(e.key.from.dot.replica);
      add_replica(e.key.to.dot.replica);
      add_symbol(e.key.type);
      for (std::uint32_t i = e.attrs.begin; i < e.attrs.end; ++i) add_symbol(d_->attrs[i].name);
    }
    for (const Dot& x : d_->removed) add_replica(x.replica);
    for (const Dot& x : d_->added) add_replica(x.replica);
    for (const Dot& x : d_->keep) add_replica(x.replica);
    for (const auto& [var, id] : d_->binding) add_replica(id.dot.replica);
    for (const auto& e : d_->values) add_replica(e.dot.replica);
    for (const auto& e : d_->claims) {
      add_replica(e.dot.replica);
      if (!e.value.parent.is_null()) add_replica(e.value.parent.dot.replica);
      if (!e.value.fallback_parent.is_null()) {
        add_replica(e.value.fallback_parent.dot.replica);
        add_replica(e.value.fallback_epoch.replica);
      }
    }
    for (const auto& s : d_->samples) {
      add_replica(s.dot.replica);
      add_replica(s.epoch.replica);
    }
  }

  // Added dots in stream order (must match the decoder's order).
  template <class F>
  void for_each_added_in_order(F&& f) const {
    for (const auto& n : d_->nodes) {
      for (std::uint32_t i = n.attrs.begin; i < n.attrs.end; ++i)
        for (std::uint32_t j = d_->attrs[i].added.begin; j < d_->attrs[i].added.end; ++j) f(d_->values[j].dot);
      for (std::uint32_t j = n.claim_added.begin; j < n.claim_added.end; ++j) f(d_->claims[j].dot);
      for (std::uint32_t j = n.samples.begin; j < n.samples.end; ++j) f(d_->samples[j].dot);
    }
    for (const auto& e : d_->edges) {
      for (std::uint32_t j = e.added.begin; j < e.added.end; ++j) f(d_->added[j]);
      for (std::uint32_t i = e.attrs.begin; i < e.attrs.end; ++i)
        for (std::uint32_t j = d_->attrs[i].added.begin; j < d_->attrs[i].added.end; ++j) f(d_->values[j].dot);
    }
  }

  void plan_dots() {
    // Implicit dots: every added dot is the origin's and they run F, F+1, ... in stream order.
    bool ok = true, first = true;
    std::uint64_t expect = 0;
    base_ = UINT64_MAX;
    for_each_added_in_order([&](const Dot& x) {
      if (x.replica == d_->origin) base_ = std::min(base_, x.counter);
      if (!ok) return;
      if (!(x.replica == d_->origin)) {
        ok = false;
        return;
      }
      if (first) {
        expect = x.counter;
        first = false;
      } else if (x.counter != expect) {
        ok = false;
        return;
      }
      ++expect;
    });
    implicit_ = ok && !first;
    if (implicit_) {
      std::uint64_t f = 0;
      bool got = false;
      for_each_added_in_order([&](const Dot& x) {
        if (!got) {
          f = x.counter;
          got = true;
        }
      });
      next_implicit_ = f;
    }
    if (base_ == UINT64_MAX) base_ = 0;
    // Sorted nodes: within each replica, node counters never decrease.
    sorted_ = true;
    for (std::size_t i = 1; i < d_->nodes.size(); ++i) {
      const Dot& a = d_->nodes[i - 1].id.dot;
      const Dot& b = d_->nodes[i].id.dot;
      if (a.replica == b.replica && b.counter < a.counter) sorted_ = false;
    }
  }

  void dot(const Dot& x) {
    w_.varint(rindex(x.replica));
    w_.varint(x.counter);
  }
  void node_ref(const NodeId& n) {
    w_.varint(n.dot.counter);
    if (n.dot.counter != 0) w_.varint(rindex(n.dot.replica));
  }
  void origin_dot(const Dot& x) {
    if (implicit_) return;
    w_.varint(x.counter - base_);
  }
  bool is_origin_dot(const Dot& x) const {
    return x.replica == d_->origin && (implicit_ || x.counter >= base_);
  }
  void pose(const Pose& p) {
    for (double v : p.translation) w_.f64(v);
    for (double v : p.rotation) w_.f64(v);
  }

  void value(const crdt::Entry<Value>& e) {
    e.value.encode(w_);
    if (fenced_) w_.varint(e.fence);
  }

  void attr(const GraphDelta::AttrOp& a) {
    std::uint64_t sym = sindex(a.name);
    const std::uint32_t nrem = a.removed.size(), nadd = a.added.size();
    if (nadd == 1 && is_origin_dot(d_->values[a.added.begin].dot)) {
      const auto& e = d_->values[a.added.begin];
      if (nrem == 0) {
        w_.varint(sym << 2 | kFresh);
        origin_dot(e.dot);
        value(e);
        return;
      }
      const Dot& old = d_->removed[a.removed.begin];
      if (nrem == 1 && old.replica == e.dot.replica && old.counter < e.dot.counter) {
        w_.varint(sym << 2 | kOverwrite);
        origin_dot(e.dot);
        w_.varint(e.dot.counter - old.counter);
        value(e);
        return;
      }
    }
    if (nadd == 0) {
      w_.varint(sym << 2 | kRemoveOnly);
      w_.varint(nrem);
      for (std::uint32_t i = a.removed.begin; i < a.removed.end; ++i) dot(d_->removed[i]);
      return;
    }
    w_.varint(sym << 2 | kGeneral);
    w_.varint(nrem);
    for (std::uint32_t i = a.removed.begin; i < a.removed.end; ++i) dot(d_->removed[i]);
    w_.varint(nadd);
    for (std::uint32_t i = a.added.begin; i < a.added.end; ++i) {
      // Under implicit dots the dot is known; otherwise it is written in full.
      if (!implicit_) dot(d_->values[i].dot);
      value(d_->values[i]);
    }
  }

  void node(const GraphDelta::NodeOp& n, const NodeId& prev) {
    bool switch_replica = prev.is_null() || !(prev.dot.replica == n.id.dot.replica);
    std::uint64_t flags = (n.has_header ? kHdr : 0) | (n.removed ? kRemoved : 0) |
                          (!n.claim_removed.empty() || !n.claim_added.empty() ? kClaims : 0) |
                          (!n.samples.empty() ? kSamples : 0) | (switch_replica ? kReplicaSwitch : 0);
    w_.varint(static_cast<std::uint64_t>(n.attrs.size()) << 5 | flags);
    if (switch_replica) {
      w_.varint(rindex(n.id.dot.replica));
      w_.varint(n.id.dot.counter);
    } else if (sorted_) {
      w_.varint(n.id.dot.counter - prev.dot.counter);
    } else {
      w_.svarint(static_cast<std::int64_t>(n.id.dot.counter - prev.dot.counter));
    }
    if (n.has_header) {
      w_.varint(sindex(n.type));
      w_.string(n.name);
    } else if (typed_) {
      w_.varint(n.type.is_null() ? 0 : sindex(n.type) + 1);
    }
    for (std::uint32_t i = n.attrs.begin; i < n.attrs.end; ++i) attr(d_->attrs[i]);
    if (flags & kClaims) {
      w_.varint(n.claim_removed.size());
      for (std::uint32_t i = n.claim_removed.begin; i < n.claim_removed.end; ++i) dot(d_->removed[i]);
      w_.varint(n.claim_added.size());
      for (std::uint32_t i = n.claim_added.begin; i < n.claim_added.end; ++i) {
        const auto& e = d_->claims[i];
        if (!implicit_) dot(e.dot);
        node_ref(e.value.parent);
        pose(e.value.pose);
        w_.svarint(e.value.stamp);
        node_ref(e.value.fallback_parent);
        if (!e.value.fallback_parent.is_null()) {
          pose(e.value.fallback_pose);
          w_.svarint(e.value.fallback_stamp);
          dot(e.value.fallback_epoch);
        }
      }
    }
    if (flags & kSamples) {
      w_.varint(n.samples.size());
      for (std::uint32_t i = n.samples.begin; i < n.samples.end; ++i) {
        const RtSample& s = d_->samples[i];
        if (!implicit_) dot(s.dot);
        w_.svarint(s.stamp);
        dot(s.epoch);
        pose(s.pose);
      }
    }
  }

  void edge(const GraphDelta::EdgeOp& e) {
    node_ref(e.key.from);
    node_ref(e.key.to);
    w_.varint(sindex(e.key.type));
    std::uint64_t flags = (!e.removed.empty() ? kEdgeRemoved : 0) | (!e.added.empty() ? kEdgeAdded : 0) |
                          (!e.attrs.empty() ? kEdgeAttrs : 0);
    w_.varint(flags);
    if (flags & kEdgeRemoved) {
      w_.varint(e.removed.size());
      for (std::uint32_t i = e.removed.begin; i < e.removed.end; ++i) dot(d_->removed[i]);
    }
    if (flags & kEdgeAdded) {
      w_.varint(e.added.size());
      if (!implicit_)
        for (std::uint32_t i = e.added.begin; i < e.added.end; ++i) dot(d_->added[i]);
    }
    if (flags & kEdgeAttrs) {
      w_.varint(e.attrs.size());
      for (std::uint32_t i = e.attrs.begin; i < e.attrs.end; ++i) attr(d_->attrs[i]);
    }
  }

  void keep(const std::vector<Dot>& kept) {
    std::vector<Dot> k = kept;
    std::sort(k.begin(), k.end());
    w_.varint(k.size());
    ReplicaId cur{};
    std::uint64_t prev = 0;
    bool first = true;
    for (const Dot& x : k) {
      // Each dot: a "same replica" flag in bit 0; counters as gaps.
      if (first || !(x.replica == cur)) {
        w_.varint(rindex(x.replica) << 1 | 1);
        w_.varint(x.counter);
        cur = x.replica;
        first = false;
      } else {
        w_.varint((x.counter - prev) << 1);
      }
      prev = x.counter;
    }
  }

  const GraphDelta* d_;  // the message, or in parts the part at hand
  bytes::Writer w_;
  std::uint64_t seq_lo_, seq_hi_;
  static constexpr std::size_t kKeptEntries = 64;
  static thread_local EncodeTables tables_;
  std::vector<ReplicaId>& replicas_ = tables_.replicas;
  std::unordered_map<ReplicaId, std::uint64_t>& rmap_ = tables_.rmap;
  std::size_t rlast_ = 0;
  std::vector<Symbol>& symbols_ = tables_.symbols;
  std::unordered_map<Symbol, std::uint64_t>& smap_ = tables_.smap;
  std::size_t slast_ = 0;
  bool implicit_ = false;
  bool sorted_ = true;
  bool fenced_ = false;
  bool typed_ = false;
  std::uint64_t next_implicit_ = 0;
  std::uint64_t base_ = 0;
};

thread_local EncodeTables Encoder::tables_;

}  // namespace

void encode(const GraphDelta& d, std::vector<std::uint8_t>& out) { encode(d, out, d.seq_lo, d.seq_hi); }

void encode(const GraphDelta& d, std::vector<std::uint8_t>& out, std::uint64_t seq_lo, std::uint64_t seq_hi) {
  // A small delta into a fresh vector (encode(d), a message kept apart) is encoded in this
  // thread's scratch and copied once at its size, rather than grown a byte at a time (a
  // one-attribute delta reallocated eight times). Not a large one: a state would pay a second
  // copy of megabytes, and a scratch that large is not worth keeping.
  constexpr std::size_t kSmall = 256;
  if (out.capacity() != 0 || d.nodes.size() + d.edges.size() + d.values.size() > kSmall)
    return Encoder(d, out, seq_lo, seq_hi).run();
  thread_local std::vector<std::uint8_t> scratch;
  scratch.clear();
  Encoder(d, scratch, seq_lo, seq_hi).run();
  out.assign(scratch.begin(), scratch.end());
  if (scratch.capacity() > 64 * 1024) std::vector<std::uint8_t>().swap(scratch);  // large values
}

void encode_parts(const PartSource& parts, std::vector<std::uint8_t>& out) {
  const GraphDelta none;
  Encoder(none, out, 0, 0).run_parts(parts);
}

std::vector<std::uint8_t> encode(const GraphDelta& d) {
  std::vector<std::uint8_t> out;
  encode(d, out);
  return out;
}

}  // namespace quiver::graph
