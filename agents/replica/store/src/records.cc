// The byte forms of what a store holds: log records and the snapshot, each sealed by a checksum of what precedes
// it, and the log's keys.
#include "quiver/agents/replica/store/records.h"

#include <array>

#include "quiver/crdt/context_codec.h"
#include "quiver/base/hash.h"
#include "quiver/base/byte_codec.h"

namespace quiver::agents::inline replica::store {
namespace {

constexpr std::uint64_t kChecksumSeed = 0x5eed5707e;
constexpr std::uint64_t kMaxPayload = std::uint64_t{1} << 40;

std::uint64_t checksum(std::span<const std::uint8_t> b) { return record_checksum(b); }

void seal(std::vector<std::uint8_t>& out) {
  const std::uint64_t c = checksum(out);
  bytes::Writer(out).fixed64(c);
}

// Checks the trailing checksum; returns the bytes before it.
Result<std::span<const std::uint8_t>> unseal(std::span<const std::uint8_t> bytes, const std::string& what) {
  if (bytes.size() < 9) return make_error(ErrorCode::kTruncated, what + ": " + std::to_string(bytes.size()) +
                                                                     " bytes, shorter than any record");
  auto body = bytes.first(bytes.size() - 8);
  bytes::Reader tail(bytes.last(8), what);
  if (tail.fixed64("checksum") != checksum(body))
    return make_error(ErrorCode::kMalformed, what + ": checksum mismatch (the bytes were damaged on disk)");
  return body;
}

}  // namespace

std::uint64_t record_checksum(std::span<const std::uint8_t> body) {
  Hasher h(kChecksumSeed);
  h.bytes(body.data(), body.size());
  return h.h64();
}

std::vector<std::uint8_t> encode_delta_record(const graph::ReplicaId& origin, std::uint64_t lo, std::uint64_t hi,
                                              std::span<const std::uint8_t> payload) {
  std::vector<std::uint8_t> out;
  out.reserve(payload.size() + 40);
  bytes::Writer w(out);
  w.u8(static_cast<std::uint8_t>(RecordKind::kDelta));
  crdt::encode_replica(origin, w);
  w.varint(lo);
  w.varint(hi);
  w.bytes(payload);
  seal(out);
  return out;
}

std::vector<std::uint8_t> encode_state_record(const crdt::CausalContext& applied,
                                              std::span<const std::uint8_t> payload) {
  std::vector<std::uint8_t> out;
  out.reserve(payload.size() + 64);
  bytes::Writer w(out);
  w.u8(static_cast<std::uint8_t>(RecordKind::kState));
  crdt::encode_context(applied, w);
  w.bytes(payload);
  seal(out);
  return out;
}

std::vector<std::uint8_t> encode_skipped_record(const graph::ReplicaId& origin, std::uint64_t lo, std::uint64_t hi) {
  std::vector<std::uint8_t> out;
  bytes::Writer w(out);
  w.u8(static_cast<std::uint8_t>(RecordKind::kSkipped));
  crdt::encode_replica(origin, w);
  w.varint(lo);
  w.varint(hi);
  seal(out);
  return out;
}

Result<Record> decode_record(std::span<const std::uint8_t> bytes, const std::string& what) {
  auto body = unseal(bytes, what);
  if (!body.ok()) return body.error();
  bytes::Reader r(*body, what);
  Record rec;
  const std::uint8_t kind = r.u8("kind");
  switch (kind) {
    case static_cast<std::uint8_t>(RecordKind::kDelta):
    case static_cast<std::uint8_t>(RecordKind::kSkipped):
      rec.kind = static_cast<RecordKind>(kind);
      rec.origin = crdt::decode_replica(r, "origin");
      rec.lo = r.varint("lo");
      rec.hi = r.varint("hi");
      if (r.ok() && (rec.lo == 0 || rec.hi < rec.lo)) r.fail(ErrorCode::kMalformed, "hi", "not an interval");
      if (rec.kind == RecordKind::kDelta) rec.payload = r.bytes("payload", kMaxPayload);
      break;
    case static_cast<std::uint8_t>(RecordKind::kState):
      rec.kind = RecordKind::kState;
      crdt::decode_context(r, rec.applied);
      rec.payload = r.bytes("payload", kMaxPayload);
      break;
    default:
      return make_error(ErrorCode::kMalformed, what + ": unknown record kind " + std::to_string(kind));
  }
  if (r.ok() && !r.at_end()) r.fail(ErrorCode::kMalformed, "end", "bytes after the record");
  if (!r.ok()) return r.error();
  return rec;
}

std::vector<std::uint8_t> encode_snapshot(std::uint64_t upto, const crdt::CausalContext& applied,
                                          std::span<const std::uint8_t> state) {
  std::vector<std::uint8_t> out;
  out.reserve(state.size() + 64);
  bytes::Writer w(out);
  w.u8(1);  // snapshot format
  w.varint(upto);
  crdt::encode_context(applied, w);
  w.bytes(state);
  seal(out);
  return out;
}

Result<Snapshot> decode_snapshot(std::span<const std::uint8_t> bytes, const std::string& what) {
  auto body = unseal(bytes, what);
  if (!body.ok()) return body.error();
  bytes::Reader r(*body, what);
  Snapshot s;
  if (const std::uint8_t v = r.u8("format"); r.ok() && v != 1)
    return make_error(ErrorCode::kUnsupportedVersion, what + ": snapshot format " + std::to_string(v) +
                                                          " (this build reads format 1)");
  s.upto = r.varint("upto");
  crdt::decode_context(r, s.applied);
  s.state = r.bytes("state", kMaxPayload);
  if (r.ok() && !r.at_end()) r.fail(ErrorCode::kMalformed, "end", "bytes after the snapshot");
  if (!r.ok()) return r.error();
  return s;
}

std::array<std::uint8_t, 8> record_key(std::uint64_t n) {
  std::array<std::uint8_t, 8> k;
  for (int i = 0; i < 8; ++i) k[i] = static_cast<std::uint8_t>(n >> (8 * (7 - i)));
  return k;
}

std::uint64_t record_number(std::span<const std::uint8_t> key) {
  std::uint64_t n = 0;
  for (std::uint8_t b : key) n = (n << 8) | b;
  return n;
}

}  // namespace quiver::agents::inline replica::store
