#include "quiver/agents/replication/frame_codec.h"

#include "quiver/crdt/context_codec.h"
#include "quiver/wire.h"

namespace quiver::agents {
namespace {

constexpr std::uint8_t kMagic0 = 'Q';
constexpr std::uint8_t kMagic1 = 'R';
enum MsgType : std::uint8_t { kSummary = 1, kDelta = 2, kPull = 3, kState = 4, kBye = 5 };
constexpr std::uint64_t kMaxBody = 1ull << 30;
constexpr std::uint64_t kMaxMessages = 1u << 20;

struct BodyWriter {
  wire::Writer& w;
  void operator()(const SummaryMsg& m) {
    w.u8(kSummary);
    w.string(m.name);
    w.varint(m.observer ? 1 : 0);
    crdt::encode_context(m.applied, w);
  }
  void operator()(const DeltaMsg& m) {
    w.u8(kDelta);
    crdt::encode_replica(m.origin, w);
    w.varint(m.lo);
    w.varint(m.hi - m.lo);
    w.bytes(*m.payload);
  }
  void operator()(const PullMsg& m) {
    w.u8(kPull);
    w.varint(m.request);
    crdt::encode_context(m.applied, w);
    crdt::encode_context(m.context, w);
  }
  void operator()(const StateMsg& m) {
    w.u8(kState);
    w.varint(m.request);
    w.varint(m.index);
    w.varint(m.count);
    if (m.index == 0) crdt::encode_context(m.applied, w);
    w.bytes(*m.chunk);
  }
  void operator()(const ByeMsg&) { w.u8(kBye); }
};

}  // namespace

std::size_t approx_size(const Message& m) {
  struct {
    std::size_t operator()(const SummaryMsg& s) { return 16 + s.name.size() + 24 * s.applied.range_count(); }
    std::size_t operator()(const DeltaMsg& d) { return 24 + d.payload->size(); }
    std::size_t operator()(const PullMsg& p) { return 16 + 24 * (p.applied.range_count() + p.context.range_count()); }
    std::size_t operator()(const StateMsg& s) { return 24 + s.chunk->size() + 24 * s.applied.range_count(); }
    std::size_t operator()(const ByeMsg&) { return 1; }
  } size;
  return std::visit(size, m);
}

void encode_frame(const Envelope& e, std::vector<std::uint8_t>& out) {
  wire::Writer w(out);
  w.u8(kMagic0);
  w.u8(kMagic1);
  w.u8(kFrameVersion);
  crdt::encode_replica(e.from, w);
  w.u8(e.to.is_null() ? 0 : 1);
  if (!e.to.is_null()) crdt::encode_replica(e.to, w);
  w.varint(e.messages.size());
  std::vector<std::uint8_t> body;
  for (const Message& m : e.messages) {
    body.clear();
    wire::Writer bw(body);
    std::visit(BodyWriter{bw}, m);
    // type byte, then the body's length and bytes
    w.u8(body[0]);
    w.varint(body.size() - 1);
    w.raw(body.data() + 1, body.size() - 1);
  }
}

std::vector<std::uint8_t> encode_frame(const Envelope& e) {
  std::vector<std::uint8_t> out;
  encode_frame(e, out);
  return out;
}

Result<Envelope> decode_frame(std::span<const std::uint8_t> frame) {
  wire::Reader r(frame, "replication frame");
  std::uint8_t m0 = r.u8("magic"), m1 = r.u8("magic"), version = r.u8("version");
  if (!r.ok()) return r.error();
  if (m0 != kMagic0 || m1 != kMagic1) {
    r.fail(ErrorCode::kMalformed, "magic", "not a Quiver replication frame");
    return r.error();
  }
  if (version != kFrameVersion) {
    r.fail(ErrorCode::kUnsupportedVersion, "version",
           "protocol version " + std::to_string(version) + " (this build speaks " + std::to_string(kFrameVersion) + ")");
    return r.error();
  }
  Envelope e;
  e.from = crdt::decode_replica(r, "sender");
  std::uint8_t unicast = r.u8("destination flag");
  if (unicast == 1) e.to = crdt::decode_replica(r, "destination");
  else if (unicast != 0 && r.ok()) r.fail(ErrorCode::kMalformed, "destination flag", "must be 0 or 1");
  std::uint64_t n = r.count("message count", kMaxMessages, 2);
  if (!r.ok()) return r.error();
  if (e.from.is_null()) {
    r.fail(ErrorCode::kMalformed, "sender", "null sender");
    return r.error();
  }
  e.messages.reserve(n);
  for (std::uint64_t i = 0; i < n; ++i) {
    std::uint8_t type = r.u8("message type");
    auto body = r.bytes("message body", kMaxBody);
    if (!r.ok()) return r.error();
    wire::Reader b(body, "replication message");
    switch (type) {
      case kSummary: {
        SummaryMsg m;
        m.name = std::string(b.string("agent name", 1024));
        std::uint64_t flags = b.varint("flags");
        if (b.ok() && flags > 1) b.fail(ErrorCode::kMalformed, "flags", "unknown flag bits");
        m.observer = flags & 1;
        crdt::decode_context(b, m.applied);
        e.messages.emplace_back(std::move(m));
        break;
      }
      case kDelta: {
        DeltaMsg m;
        m.origin = crdt::decode_replica(b, "origin");
        m.lo = b.varint("first sequence number");
        std::uint64_t len = b.varint("sequence count");
        auto payload = b.bytes("delta", kMaxBody);
        if (b.ok() && (m.lo == 0 || m.lo + len < m.lo)) b.fail(ErrorCode::kMalformed, "sequence numbers", "invalid range");
        if (b.ok() && m.origin.is_null()) b.fail(ErrorCode::kMalformed, "origin", "null origin");
        m.hi = m.lo + len;
        m.payload = std::make_shared<const std::vector<std::uint8_t>>(payload.begin(), payload.end());
        e.messages.emplace_back(std::move(m));
        break;
      }
      case kPull: {
        PullMsg m;
        m.request = b.varint("request id");
        crdt::decode_context(b, m.applied);
        crdt::decode_context(b, m.context);
        e.messages.emplace_back(std::move(m));
        break;
      }
      case kState: {
        StateMsg m;
        m.request = b.varint("request id");
        std::uint64_t index = b.varint("chunk index");
        std::uint64_t count = b.bounded("chunk count", kMaxMessages);
        if (b.ok() && (count == 0 || index >= count)) b.fail(ErrorCode::kMalformed, "chunk index", "out of range");
        m.index = static_cast<std::uint32_t>(index);
        m.count = static_cast<std::uint32_t>(count);
        if (index == 0) crdt::decode_context(b, m.applied);
        auto chunk = b.bytes("chunk", kMaxBody);
        m.chunk = std::make_shared<const std::vector<std::uint8_t>>(chunk.begin(), chunk.end());
        e.messages.emplace_back(std::move(m));
        break;
      }
      case kBye: e.messages.emplace_back(ByeMsg{}); break;
      default:
        r.fail(ErrorCode::kMalformed, "message type", "unknown message type " + std::to_string(type));
        return r.error();
    }
    if (!b.ok()) return b.error();
    if (!b.at_end()) {
      b.fail(ErrorCode::kMalformed, "message end", std::to_string(b.remaining()) + " trailing bytes in a message");
      return b.error();
    }
  }
  if (!r.at_end()) {
    r.fail(ErrorCode::kMalformed, "frame end", std::to_string(r.remaining()) + " trailing bytes after the messages");
    return r.error();
  }
  return e;
}

}  // namespace quiver::agents
