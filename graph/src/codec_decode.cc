// The GraphDelta decoder: bounds-checked reading of the wire format of codec_format.h, with
// symbols provisional until the whole message has been read and checked.

#include <algorithm>
#include <unordered_map>

#include "codec_format.h"
#include "quiver/base/byte_codec.h"
#include "quiver/graph/codec.h"

namespace quiver::graph {
namespace {

using namespace internal;

// A message's tables, kept per thread from one message to the next: decoding a delta like the
// last one allocates nothing. Tables a large state grew are released after it.
struct DecodeTables {
  std::vector<ReplicaId> replicas;
  std::vector<Symbol> symbols;
  std::vector<std::string_view> names;
};

class Decoder {
 public:
  Decoder(std::span<const std::uint8_t> in, GraphDelta& out, const DecodeLimits& lim,
          const PartSink* sink = nullptr, std::size_t part_ops = 0)
      : r_(in, "graph delta"), d_(out), lim_(lim), sink_(sink), part_ops_(std::max<std::size_t>(part_ops, 1)) {
    replicas_.clear();
    symbols_.clear();
    names_.clear();
  }
  ~Decoder() {
    if (replicas_.capacity() + symbols_.capacity() > kKeptEntries) tables_ = DecodeTables{};
    names_.clear();  // they view the input
  }
  Decoder(const Decoder&) = delete;
  Decoder& operator=(const Decoder&) = delete;

  Status run() {
    d_.clear();
    std::uint8_t m0 = r_.u8("magic"), m1 = r_.u8("magic");
    if (r_.ok() && (m0 != kMagic0 || m1 != kMagic1)) return fail(ErrorCode::kMalformed, "magic", "not a Quiver graph message");
    std::uint8_t version = r_.u8("version");
    if (r_.ok() && version != kCodecVersion)
      return fail(ErrorCode::kUnsupportedVersion, "version",
                  "format version " + std::to_string(version) + " is not supported (this build reads " +
                      std::to_string(kCodecVersion) + ")");
    std::uint8_t kind = r_.u8("kind");
    if (r_.ok() && kind != 1 && kind != 2) return fail(ErrorCode::kMalformed, "kind", "unknown message kind " + std::to_string(kind));
    d_.kind = static_cast<GraphDelta::Kind>(kind);
    std::uint64_t flags = r_.varint("flags");
    if (flags & ~kAllFlags) return fail(ErrorCode::kMalformed, "flags", "unknown flag bits");
    if (flags & kSeq) {
      d_.seq_lo = r_.varint("sequence interval");
      std::uint64_t len = r_.varint("sequence interval length");
      if (r_.ok() && (d_.seq_lo == 0 || len > crdt::kMaxCounter - d_.seq_lo))
        return fail(ErrorCode::kMalformed, "sequence interval", "invalid sequence numbers");
      d_.seq_hi = d_.seq_lo + len;
    }
    const bool claim = flags & kClaim;
    implicit_ = flags & kImplicitDots;
    sorted_ = flags & kSortedNodes;
    fenced_ = flags & kFenced;
    typed_ = flags & kTyped;

    std::uint64_t nrep = r_.count("replica count", lim_.max_table, 2);
    if (r_.ok() && nrep == 0) return fail(ErrorCode::kMalformed, "replica count", "the replica table is empty");
    replicas_.resize(nrep);
    for (auto& rep : replicas_) {
      rep.agent = r_.fixed64("replica agent");
      rep.incarnation = r_.varint("replica incarnation");
    }
    if (!r_.ok()) return r_.error();
    d_.origin = replicas_[0];
    std::uint64_t nsym = r_.count("symbol count", lim_.max_table, 1);
    symbols_.resize(nsym);
    symbols::rt();  // interned before any lookup, so "RT" is never provisional
    names_.resize(nsym);
    for (std::size_t i = 0; i < nsym; ++i) {
      std::string_view name = r_.string("symbol", lim_.max_name_bytes);
      if (!r_.ok()) return r_.error();
      if (name.empty()) return fail(ErrorCode::kMalformed, "symbol", "empty symbol");
      if (!valid_utf8(name)) return fail(ErrorCode::kMalformed, "symbol", "a name is not valid UTF-8");
      names_[i] = name;
      symbols_[i] = Symbol::find(name);
      if (symbols_[i].is_null()) {
        symbols_[i] = Symbol::from_index(kProvisional | static_cast<std::uint32_t>(i));
        provisional_ = true;
      }
    }
    std::uint64_t nranges = r_.count("context range count", UINT32_MAX, 3);
    for (std::uint64_t i = 0; i < nranges && r_.ok(); ++i) {
      const ReplicaId* rep = replica("context replica");
      std::uint64_t lo = r_.varint("context lo");
      std::uint64_t len = r_.varint("context length");
      if (!r_.ok()) break;
      if (lo == 0 || lo > crdt::kMaxCounter || len > crdt::kMaxCounter - lo)
        return fail(ErrorCode::kMalformed, "context range", "invalid counter range");
      d_.context.add_range(*rep, lo, lo + len);
    }
    if (implicit_) next_implicit_ = r_.varint("first implicit dot");
    else base_ = r_.varint("dot base");
    if (implicit_ && r_.ok() && (next_implicit_ == 0 || next_implicit_ > crdt::kMaxCounter))
      return fail(ErrorCode::kMalformed, "first implicit dot", "invalid counter");

    if (sink_ != nullptr && d_.kind != GraphDelta::Kind::kState)
      return fail(ErrorCode::kMalformed, "kind", "only a state is decoded in parts");
    std::uint64_t nnodes = r_.count("node count", UINT32_MAX, 2);
    d_.nodes.reserve(sink_ == nullptr ? nnodes : std::min<std::uint64_t>(nnodes, part_ops_));
    NodeId prev{};
    for (std::uint64_t i = 0; i < nnodes && r_.ok(); ++i) {
      node(prev);
      if (r_.ok()) prev = d_.nodes.back().id;
      if (Status s = part_full(); !s.ok()) return s;
    }
    std::uint64_t nedges = r_.count("edge count", UINT32_MAX, 4);
    for (std::uint64_t i = 0; i < nedges && r_.ok(); ++i) {
      edge();
      if (Status s = part_full(); !s.ok()) return s;
    }
    if (claim && r_.ok()) {
      d_.rule = std::string(r_.string("claimed rule", lim_.max_name_bytes));
      if (r_.ok() && (d_.rule.empty() || !valid_utf8(d_.rule)))
        return fail(ErrorCode::kMalformed, "claimed rule", "empty or not UTF-8");
      std::uint64_t nb = r_.count("claim binding count", lim_.max_table, 2);
      for (std::uint64_t i = 0; i < nb && r_.ok(); ++i) {
        std::string var(r_.string("claim variable", lim_.max_name_bytes));
        NodeId id = node_ref("claim node");
        if (r_.ok() && (var.empty() || !valid_utf8(var) || id.is_null()))
          return fail(ErrorCode::kMalformed, "claim binding", "empty or non-UTF-8 variable, or null node");
        d_.binding.emplace_back(std::move(var), id);
      }
    }
    if (d_.kind == GraphDelta::Kind::kState) keep();
    if (!r_.ok()) return r_.error();
    if (!r_.at_end())
      return fail(ErrorCode::kMalformed, "end", std::to_string(r_.remaining()) + " trailing bytes after the message");
    if (d_.kind == GraphDelta::Kind::kDelta)
      if (Status s = check_delta(); !s.ok()) return s;
    if (provisional_)
      if (Status s = intern_names(); !s.ok()) return s;
    if (sink_ != nullptr) return (*sink_)(d_);  // the last part: the rest, and the keep list
    return {};
  }

 private:
  // In parts: a part holding part_ops_ node and edge ops goes to the sink, and its ops make way
  // for the next (the context stays: every part carries the message's).
  Status part_full() {
    if (sink_ == nullptr || !r_.ok() || d_.nodes.size() + d_.edges.size() < part_ops_) return {};
    if (Status s = (*sink_)(d_); !s.ok()) return s;
    d_.clear_ops();  // the keep list comes after the last op
    return {};
  }

  Status fail(ErrorCode code, const char* field, const std::string& why) {
    r_.fail(code, field, why);
    return r_.error();
  }
  const ReplicaId* replica(const char* field) {
    std::uint64_t i = r_.varint(field);
    if (!r_.ok()) return &replicas_[0];
    if (i >= replicas_.size()) {
      r_.fail(ErrorCode::kMalformed, field, "replica index " + std::to_string(i) + " is out of the table (" +
                                                std::to_string(replicas_.size()) + " entries)");
      return &replicas_[0];
    }
    return &replicas_[i];
  }
  Symbol symbol(const char* field) {
    std::uint64_t i = r_.varint(field);
    if (!r_.ok()) return Symbol();
    if (i >= symbols_.size()) {
      r_.fail(ErrorCode::kMalformed, field, "symbol index " + std::to_string(i) + " is out of the table");
      return Symbol();
    }
    return symbols_[i];
  }
  void check_counter(std::uint64_t c, const char* field) {
    if (r_.ok() && c == 0) r_.fail(ErrorCode::kMalformed, field, "dot counter 0");
    if (r_.ok() && c > crdt::kMaxCounter)
      r_.fail(ErrorCode::kMalformed, field, "counter " + std::to_string(c) + " exceeds the limit 2^53-1");
  }
  Dot dot(const char* field) {
    const ReplicaId* rep = replica(field);
    std::uint64_t c = r_.varint(field);
    check_counter(c, field);
    return Dot{*rep, c};
  }
  NodeId node_ref(const char* field) {
    std::uint64_t c = r_.varint(field);
    if (!r_.ok() || c == 0) return NodeId{};
    check_counter(c, field);
    const ReplicaId* rep = replica(field);
    return NodeId{Dot{*rep, c}};
  }
  Dot origin_dot(const char* field) {
    if (implicit_) {
      check_counter(next_implicit_, field);
      return Dot{d_.origin, next_implicit_++};
    }
    std::uint64_t off = r_.varint(field);
    if (r_.ok() && off > crdt::kMaxCounter - std::min(base_, crdt::kMaxCounter))
      r_.fail(ErrorCode::kMalformed, field, "dot offset overflows");
    check_counter(base_ + off, field);
    return Dot{d_.origin, base_ + off};
  }
  Dot entry_dot(const char* field) { return implicit_ ? origin_dot(field) : dot(field); }
  Pose pose() {
    Pose p;
    for (double& v : p.translation) v = r_.f64("pose translation");
    for (double& v : p.rotation) v = r_.f64("pose rotation");
    return p;
  }
  // A value and, in fenced messages, its fencing epoch.
  crdt::Entry<Value> entry(const Dot& d) {
    crdt::Entry<Value> e{d, Value::decode(r_, lim_.max_value_bytes), 0};
    if (fenced_) e.fence = r_.varint("value fence");
    return e;
  }

  void attr() {
    GraphDelta::AttrOp a;
    std::uint64_t hdr = r_.varint("attribute header");
    std::uint64_t sidx = hdr >> 2;
    if (r_.ok() && sidx >= symbols_.size()) {
      r_.fail(ErrorCode::kMalformed, "attribute name", "symbol index " + std::to_string(sidx) + " is out of the table");
      return;
    }
    a.name = symbols_.empty() ? Symbol() : symbols_[sidx];
    a.removed = {u32(d_.removed.size()), u32(d_.removed.size())};
    a.added = {u32(d_.values.size()), u32(d_.values.size())};
    switch (hdr & 3) {
      case kFresh:
      case kOverwrite: {
        Dot x = origin_dot("attribute dot");
        if ((hdr & 3) == kOverwrite) {
          std::uint64_t gap = r_.varint("overwritten dot gap");
          if (r_.ok() && (gap == 0 || gap >= x.counter)) {
            r_.fail(ErrorCode::kMalformed, "overwritten dot gap", "gap " + std::to_string(gap) + " is invalid");
            return;
          }
          d_.removed.push_back(Dot{x.replica, x.counter - gap});
        }
        d_.values.push_back(entry(x));
        break;
      }
      case kRemoveOnly:
      case kGeneral: {
        std::uint64_t nrem = r_.count("removed dot count", UINT32_MAX, 2);
        for (std::uint64_t i = 0; i < nrem && r_.ok(); ++i) d_.removed.push_back(dot("removed dot"));
        if ((hdr & 3) == kGeneral) {
          std::uint64_t nadd = r_.count("value count", UINT32_MAX, 1);
          for (std::uint64_t i = 0; i < nadd && r_.ok(); ++i) {
            Dot x = entry_dot("value dot");
            d_.values.push_back(entry(x));
          }
        }
        break;
      }
    }
    a.removed.end = u32(d_.removed.size());
    a.added.end = u32(d_.values.size());
    d_.attrs.push_back(a);
  }

  void node(const NodeId& prev) {
    GraphDelta::NodeOp n;
    std::uint64_t hdr = r_.varint("node header");
    std::uint64_t flags = hdr & 31;
    std::uint64_t nattrs = hdr >> 5;
    if (!r_.ok()) return;
    if (nattrs > r_.remaining()) {
      r_.fail(ErrorCode::kTruncated, "node attribute count", "more attributes than bytes remain");
      return;
    }
    if (flags & kReplicaSwitch || prev.is_null()) {
      if (!(flags & kReplicaSwitch)) {
        r_.fail(ErrorCode::kMalformed, "node header", "the first node must name its replica");
        return;
      }
      const ReplicaId* rep = replica("node replica");
      n.id = NodeId{Dot{*rep, r_.varint("node counter")}};
    } else if (sorted_) {
      std::uint64_t delta = r_.varint("node counter delta");
      if (prev.dot.counter + delta < prev.dot.counter) {
        r_.fail(ErrorCode::kMalformed, "node counter delta", "overflow");
        return;
      }
      n.id = NodeId{Dot{prev.dot.replica, prev.dot.counter + delta}};
    } else {
      std::int64_t delta = r_.svarint("node counter delta");
      n.id = NodeId{Dot{prev.dot.replica, prev.dot.counter + static_cast<std::uint64_t>(delta)}};
    }
    check_counter(n.id.dot.counter, "node id");
    if (!r_.ok()) return;
    n.has_header = flags & kHdr;
    n.removed = flags & kRemoved;
    if (n.has_header) {
      n.type = symbol("node type");
      n.name = std::string(r_.string("node name", lim_.max_name_bytes));
      if (r_.ok() && (n.name.empty() || !valid_utf8(n.name) || n.name.find('~') != std::string::npos)) {
        r_.fail(ErrorCode::kMalformed, "node name", "a node name is empty, not UTF-8 or holds the reserved '~'");
        return;
      }
    } else if (typed_) {
      std::uint64_t t = r_.varint("node type (stated)");
      if (r_.ok() && t > symbols_.size()) {
        r_.fail(ErrorCode::kMalformed, "node type (stated)", "symbol index " + std::to_string(t - 1) + " is out of the table");
        return;
      }
      if (t != 0) n.type = symbols_[t - 1];
    }
    n.attrs.begin = u32(d_.attrs.size());
    for (std::uint64_t i = 0; i < nattrs && r_.ok(); ++i) attr();
    n.attrs.end = u32(d_.attrs.size());
    n.claim_removed = {u32(d_.removed.size()), u32(d_.removed.size())};
    n.claim_added = {u32(d_.claims.size()), u32(d_.claims.size())};
    if (flags & kClaims) {
      std::uint64_t nrem = r_.count("claim removed count", UINT32_MAX, 2);
      for (std::uint64_t i = 0; i < nrem && r_.ok(); ++i) d_.removed.push_back(dot("claim removed dot"));
      n.claim_removed.end = u32(d_.removed.size());
      std::uint64_t nadd = r_.count("claim count", UINT32_MAX, 57);
      for (std::uint64_t i = 0; i < nadd && r_.ok(); ++i) {
        crdt::Entry<RtClaim> e;
        e.dot = entry_dot("claim dot");
        e.value.parent = node_ref("claim parent");
        e.value.pose = pose();
        e.value.stamp = r_.svarint("claim stamp");
        e.value.fallback_parent = node_ref("claim fallback parent");
        if (!e.value.fallback_parent.is_null()) {
          e.value.fallback_pose = pose();
          e.value.fallback_stamp = r_.svarint("claim fallback stamp");
          e.value.fallback_epoch = dot("claim fallback epoch");
        }
        if (r_.ok() && (e.value.parent == n.id || e.value.fallback_parent == n.id)) {
          r_.fail(ErrorCode::kMalformed, "claim parent", "a node cannot be its own RT parent");
          return;
        }
        d_.claims.push_back(e);
      }
      n.claim_added.end = u32(d_.claims.size());
    }
    n.samples = {u32(d_.samples.size()), u32(d_.samples.size())};
    if (flags & kSamples) {
      std::uint64_t ns = r_.count("sample count", UINT32_MAX, 58);
      for (std::uint64_t i = 0; i < ns && r_.ok(); ++i) {
        RtSample s;
        s.dot = entry_dot("sample dot");
        s.stamp = r_.svarint("sample stamp");
        s.epoch = dot("sample epoch");
        s.pose = pose();
        d_.samples.push_back(s);
      }
      n.samples.end = u32(d_.samples.size());
    }
    d_.nodes.push_back(std::move(n));
  }

  void edge() {
    GraphDelta::EdgeOp e;
    e.key.from = node_ref("edge from");
    e.key.to = node_ref("edge to");
    e.key.type = symbol("edge type");
    std::uint64_t flags = r_.varint("edge flags");
    if (!r_.ok()) return;
    if (e.key.from.is_null() || e.key.to.is_null()) {
      r_.fail(ErrorCode::kMalformed, "edge endpoint", "null edge endpoint");
      return;
    }
    if (e.key.type == symbols::rt()) {
      r_.fail(ErrorCode::kMalformed, "edge type", "RT edges travel as claims, not as symbolic edges");
      return;
    }
    if (flags & ~std::uint64_t{7}) {
      r_.fail(ErrorCode::kMalformed, "edge flags", "unknown flag bits");
      return;
    }
    e.removed = {u32(d_.removed.size()), u32(d_.removed.size())};
    e.added = {u32(d_.added.size()), u32(d_.added.size())};
    e.attrs = {u32(d_.attrs.size()), u32(d_.attrs.size())};
    if (flags & kEdgeRemoved) {
      std::uint64_t n = r_.count("edge removed count", UINT32_MAX, 2);
      for (std::uint64_t i = 0; i < n && r_.ok(); ++i) d_.removed.push_back(dot("edge removed dot"));
      e.removed.end = u32(d_.removed.size());
    }
    if (flags & kEdgeAdded) {
      // Implicit dots take no bytes, so their count is capped instead (an edge gains one
      // existence dot per insert; a handful at most after concurrent inserts).
      std::uint64_t n = implicit_ ? r_.bounded("edge added count", 64) : r_.count("edge added count", UINT32_MAX, 2);
      for (std::uint64_t i = 0; i < n && r_.ok(); ++i) d_.added.push_back(entry_dot("edge added dot"));
      e.added.end = u32(d_.added.size());
    }
    if (flags & kEdgeAttrs) {
      std::uint64_t n = r_.count("edge attribute count", UINT32_MAX, 2);
      for (std::uint64_t i = 0; i < n && r_.ok(); ++i) attr();
      e.attrs.end = u32(d_.attrs.size());
    }
    d_.edges.push_back(e);
  }

  void keep() {
    std::uint64_t n = r_.count("keep count", UINT32_MAX, 1);
    d_.keep.reserve(n);
    ReplicaId cur{};
    std::uint64_t prev = 0;
    bool have = false;
    for (std::uint64_t i = 0; i < n && r_.ok(); ++i) {
      std::uint64_t v = r_.varint("keep dot");
      if (v & 1) {
        cur = *replica_at(v >> 1, "keep replica");
        prev = r_.varint("keep counter");
        have = true;
      } else {
        if (!have) {
          r_.fail(ErrorCode::kMalformed, "keep dot", "the first kept dot must name its replica");
          return;
        }
        if (prev + (v >> 1) < prev) {
          r_.fail(ErrorCode::kMalformed, "keep dot", "overflow");
          return;
        }
        prev += v >> 1;
      }
      check_counter(prev, "keep dot");
      if (!r_.ok()) return;
      d_.keep.push_back(Dot{cur, prev});
    }
  }
  const ReplicaId* replica_at(std::uint64_t i, const char* field) {
    if (i >= replicas_.size()) {
      r_.fail(ErrorCode::kMalformed, field, "replica index out of the table");
      return &replicas_[0];
    }
    return &replicas_[i];
  }

  // A delta is one replica's change: it changes something, and every dot it adds (values,
  // claims, samples, edge existence, node creations) and every range of its context is its
  // origin's, each added dot inside that context. Removed dots may be anyone's.
  Status check_delta() {
    if (d_.nodes.empty() && d_.edges.empty())
      return fail(ErrorCode::kMalformed, "delta", "a delta that changes nothing");
    Status bad;
    d_.context.for_each_range([&](const ReplicaId& rep, std::uint64_t, std::uint64_t) {
      if (bad.ok() && !(rep == d_.origin))
        bad = make_error(ErrorCode::kMalformed, "graph delta: its context names dots of " + rep.to_string() +
                                                    ", not of its origin " + d_.origin.to_string());
    });
    if (!bad.ok()) return bad;
    auto own = [&](const Dot& x, const char* what) {
      if (!bad.ok()) return;
      if (!(x.replica == d_.origin))
        bad = make_error(ErrorCode::kMalformed, std::string("graph delta: ") + what + " " + x.to_string() +
                                                    " is not a dot of its origin " + d_.origin.to_string());
      else if (!d_.context.contains(x))
        bad = make_error(ErrorCode::kMalformed,
                         std::string("graph delta: ") + what + " " + x.to_string() + " lies outside its context");
    };
    for (const Dot& x : d_.added) own(x, "edge dot");
    for (const auto& e : d_.values) own(e.dot, "value dot");
    for (const auto& e : d_.claims) own(e.dot, "RT claim dot");
    for (const auto& x : d_.samples) own(x.dot, "RT sample dot");
    for (const auto& n : d_.nodes)
      if (n.has_header) own(n.id.dot, "created node");
    return bad;
  }

  // After a successful read: the new names enter the table, and the provisional symbols in the
  // delta are replaced by them.
  Status intern_names() {
    for (std::size_t i = 0; i < symbols_.size(); ++i) {
      if (!(symbols_[i].index() & kProvisional)) continue;
      auto s = Symbol::make(names_[i]);
      if (!s.ok()) return fail(ErrorCode::kTooLarge, "symbol", s.error().message);
      symbols_[i] = *s;
    }
    auto real = [&](Symbol& s) {
      if (s.index() & kProvisional) s = symbols_[s.index() & ~kProvisional];
    };
    for (auto& n : d_.nodes) real(n.type);
    for (auto& a : d_.attrs) real(a.name);
    for (auto& e : d_.edges) real(e.key.type);
    return {};
  }

  bytes::Reader r_;
  GraphDelta& d_;
  const DecodeLimits& lim_;
  const PartSink* sink_;
  std::size_t part_ops_;
  static constexpr std::size_t kKeptEntries = 64;
  static thread_local DecodeTables tables_;
  std::vector<ReplicaId>& replicas_ = tables_.replicas;
  std::vector<Symbol>& symbols_ = tables_.symbols;
  std::vector<std::string_view>& names_ = tables_.names;  // the message's table, viewing the input
  bool provisional_ = false;
  bool implicit_ = false;
  bool sorted_ = false;
  bool fenced_ = false;
  bool typed_ = false;
  std::uint64_t next_implicit_ = 0;
  std::uint64_t base_ = 0;
};

thread_local DecodeTables Decoder::tables_;

}  // namespace

Status decode(std::span<const std::uint8_t> in, GraphDelta& out, const DecodeLimits& limits) {
  return Decoder(in, out, limits).run();
}

Status decode_parts(std::span<const std::uint8_t> in, GraphDelta& scratch, std::size_t part_ops, const PartSink& part,
                    const DecodeLimits& limits) {
  return Decoder(in, scratch, limits, &part, part_ops).run();
}

Result<GraphDelta> decode(std::span<const std::uint8_t> in, const DecodeLimits& limits) {
  GraphDelta d;
  Status s = decode(in, d, limits);
  if (!s.ok()) return s.error();
  return d;
}

}  // namespace quiver::graph
