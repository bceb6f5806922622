#include "quiver/agents/replica/replication/packet_codec.h"

#include "quiver/crdt/context_codec.h"
#include "quiver/base/byte_codec.h"

namespace quiver::agents::inline replica {
namespace {

constexpr std::uint8_t kMagic0 = 'Q';
constexpr std::uint8_t kMagic1 = 'R';
enum MsgType : std::uint8_t { kSummary = 1, kDelta = 2, kPull = 3, kState = 4, kBye = 5 };
// Decoding bounds only what it must to stay safe (a count against the bytes that remain, a
// length within the input). What a message may hold is checked by validate() for every
// transport alike.
constexpr std::uint64_t kMaxBody = 1ull << 32;

// Range lists, grouped by runs of one replica: run count, then per run the replica, its range
// count and the ranges as (gap from the previous hi, hi - lo). Any values decode; validate()
// judges them.
void encode_ranges(const RangeList& ranges, bytes::Writer& w) {
  std::size_t runs = 0;
  for (std::size_t i = 0; i < ranges.size(); ++i) runs += (i == 0 || !(ranges[i].replica == ranges[i - 1].replica));
  w.varint(runs);
  for (std::size_t i = 0; i < ranges.size();) {
    std::size_t j = i;
    while (j < ranges.size() && ranges[j].replica == ranges[i].replica) ++j;
    crdt::encode_replica(ranges[i].replica, w);
    w.varint(j - i);
    std::uint64_t prev = 0;
    for (std::size_t k = i; k < j; ++k) {
      w.svarint(static_cast<std::int64_t>(ranges[k].lo - prev));
      w.svarint(static_cast<std::int64_t>(ranges[k].hi - ranges[k].lo));
      prev = ranges[k].hi;
    }
    i = j;
  }
}

void decode_ranges(bytes::Reader& r, RangeList& out) {
  std::uint64_t runs = r.count("range runs", kMaxBody, 10);
  for (std::uint64_t i = 0; i < runs && r.ok(); ++i) {
    PeerId replica = crdt::decode_replica(r, "range replica");
    std::uint64_t n = r.count("range count", kMaxBody, 2);
    std::uint64_t prev = 0;
    for (std::uint64_t k = 0; k < n && r.ok(); ++k) {
      std::uint64_t lo = prev + static_cast<std::uint64_t>(r.svarint("range gap"));
      std::uint64_t hi = lo + static_cast<std::uint64_t>(r.svarint("range length"));
      out.push_back(Range{replica, lo, hi});
      prev = hi;
    }
  }
}

struct BodyWriter {
  bytes::Writer& w;
  void operator()(const SummaryMsg& m) {
    w.u8(kSummary);
    w.string(m.name);
    w.varint((m.observer ? 1 : 0) | (m.digest != 0 ? 2 : 0));
    encode_ranges(m.applied, w);
    if (m.digest != 0) w.fixed64(m.digest);
  }
  void operator()(const DeltaMsg& m) {
    w.u8(kDelta);
    crdt::encode_replica(m.origin, w);
    w.varint(m.lo);
    w.varint(m.hi);
    w.bytes(*m.payload);
    w.bytes(m.signature ? std::span<const std::uint8_t>(*m.signature) : std::span<const std::uint8_t>());
  }
  void operator()(const PullMsg& m) {
    w.u8(kPull);
    w.varint(m.request);
    w.varint((m.whole_state ? 1 : 0) | (m.as_state ? 2 : 0));
    encode_ranges(m.applied, w);
    encode_ranges(m.context, w);
  }
  void operator()(const StateMsg& m) {
    w.u8(kState);
    w.varint(m.request);
    w.varint(m.index);
    w.varint(m.count);
    encode_ranges(m.applied, w);
    w.bytes(*m.chunk);
  }
  void operator()(const ByeMsg&) { w.u8(kBye); }
};

}  // namespace

void encode_packet(const Envelope& e, std::vector<std::uint8_t>& out) {
  bytes::Writer w(out);
  w.u8(kMagic0);
  w.u8(kMagic1);
  w.u8(kPacketVersion);
  crdt::encode_replica(e.from, w);
  w.u8(e.to.is_null() ? 0 : 1);
  if (!e.to.is_null()) crdt::encode_replica(e.to, w);
  w.varint(e.messages.size());
  std::vector<std::uint8_t> body;
  for (const Message& m : e.messages) {
    body.clear();
    bytes::Writer bw(body);
    std::visit(BodyWriter{bw}, m);
    // type byte, then the body's length and bytes
    w.u8(body[0]);
    w.varint(body.size() - 1);
    w.raw(body.data() + 1, body.size() - 1);
  }
}

std::vector<std::uint8_t> encode_packet(const Envelope& e) {
  std::vector<std::uint8_t> out;
  encode_packet(e, out);
  return out;
}

Result<Envelope> decode_packet(std::span<const std::uint8_t> packet) {
  bytes::Reader r(packet, "replication packet");
  std::uint8_t m0 = r.u8("magic"), m1 = r.u8("magic"), version = r.u8("version");
  if (!r.ok()) return r.error();
  if (m0 != kMagic0 || m1 != kMagic1) {
    r.fail(ErrorCode::kMalformed, "magic", "not a Quiver replication packet");
    return r.error();
  }
  if (version != kPacketVersion) {
    r.fail(ErrorCode::kUnsupportedVersion, "version",
           "protocol version " + std::to_string(version) + " (this build speaks " + std::to_string(kPacketVersion) + ")");
    return r.error();
  }
  Envelope e;
  e.from = crdt::decode_replica(r, "sender");
  std::uint8_t unicast = r.u8("destination flag");
  if (unicast == 1) e.to = crdt::decode_replica(r, "destination");
  else if (unicast != 0 && r.ok()) r.fail(ErrorCode::kMalformed, "destination flag", "must be 0 or 1");
  std::uint64_t n = r.count("message count", kMaxBody, 2);
  if (!r.ok()) return r.error();
  e.messages.reserve(n);
  for (std::uint64_t i = 0; i < n; ++i) {
    std::uint8_t type = r.u8("message type");
    auto body = r.bytes("message body", kMaxBody);
    if (!r.ok()) return r.error();
    bytes::Reader b(body, "replication message");
    switch (type) {
      case kSummary: {
        SummaryMsg m;
        m.name = std::string(b.string("agent name", kMaxBody));
        std::uint64_t flags = b.varint("flags");
        if (b.ok() && flags > 3) b.fail(ErrorCode::kMalformed, "flags", "unknown flag bits");
        m.observer = flags & 1;
        decode_ranges(b, m.applied);
        if (flags & 2) m.digest = b.fixed64("state digest");
        e.messages.emplace_back(std::move(m));
        break;
      }
      case kDelta: {
        DeltaMsg m;
        m.origin = crdt::decode_replica(b, "origin");
        m.lo = b.varint("first sequence number");
        m.hi = b.varint("last sequence number");
        auto payload = b.bytes("delta", kMaxBody);
        m.payload = std::make_shared<const std::vector<std::uint8_t>>(payload.begin(), payload.end());
        auto signature = b.bytes("signature", kMaxBody);
        if (!signature.empty())
          m.signature = std::make_shared<const std::vector<std::uint8_t>>(signature.begin(), signature.end());
        e.messages.emplace_back(std::move(m));
        break;
      }
      case kPull: {
        PullMsg m;
        m.request = b.varint("request id");
        const std::uint64_t flags = b.varint("flags");
        if (b.ok() && flags > 3) b.fail(ErrorCode::kMalformed, "flags", "unknown flag bits");
        m.whole_state = flags & 1;
        m.as_state = flags & 2;
        decode_ranges(b, m.applied);
        decode_ranges(b, m.context);
        e.messages.emplace_back(std::move(m));
        break;
      }
      case kState: {
        StateMsg m;
        m.request = b.varint("request id");
        m.index = b.varint("chunk index");
        m.count = b.varint("chunk count");
        decode_ranges(b, m.applied);
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
    r.fail(ErrorCode::kMalformed, "packet end", std::to_string(r.remaining()) + " trailing bytes after the messages");
    return r.error();
  }
  return e;
}

}  // namespace quiver::agents
