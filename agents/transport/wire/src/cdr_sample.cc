// The protocol's samples as serialized CDR, without any DDS entity: the bytes Cyclone ships for a message, and
// received bytes decoded and handed to the replicator.
#include "quiver/agents/transport/wire/cdr_sample.h"

#include <dds/ddsi/ddsi_cdrstream.h>
#include <dds/ddsrt/endian.h>

#include <cstdlib>
#include <cstring>
#include <memory>

#include "quiver/agents/replica/replication/replicator.h"
#include "samples.h"

namespace quiver::agents::inline transport {
namespace {

constexpr bool kHostLittleEndian = DDSRT_ENDIAN == DDSRT_LITTLE_ENDIAN;
constexpr std::uint32_t kCdrSizeMax = 0xfffffff0u;  // Cyclone's bound on a serialized body
// Zeroed bytes after a copied body: Cyclone 0.10's XCDR2 check of a trailing 8-byte field looks
// at only 4 bytes, so normalizing may touch up to 4 bytes past the end. They absorb that, and
// the result is refused (see below).
constexpr std::size_t kSlack = 8;

Error bad(ErrorCode code, DdsTopic t, const std::string& why) {
  return make_error(code, std::string("CDR sample of ") + topic_name(t) + ": " + why);
}

}  // namespace

const char* topic_name(DdsTopic t) {
  static constexpr const char* kNames[kDdsTopicCount] = {"quiver_summary", "quiver_delta", "quiver_pull",
                                                         "quiver_state", "quiver_bye"};
  return kNames[static_cast<std::size_t>(t)];
}

DdsTopic topic_of(const Message& m) {
  static constexpr DdsTopic kTopics[] = {DdsTopic::kSummary, DdsTopic::kDelta, DdsTopic::kPull, DdsTopic::kState,
                                         DdsTopic::kBye};
  return kTopics[m.index()];
}

Result<Sample> decode_cdr_sample(DdsTopic topic, std::span<const std::uint8_t> bytes) {
  const dds_topic_descriptor_t& desc = wire::descriptor(topic);
  if (bytes.size() < 4) return bad(ErrorCode::kTruncated, topic, "shorter than its 4-byte header");
  // The representation id (big-endian): XCDR1 00 00/00 01, XCDR2 00 06/00 07 (low bit: LE).
  if (bytes[0] != 0) return bad(ErrorCode::kMalformed, topic, "unknown representation");
  std::uint32_t xcdr;
  switch (bytes[1]) {
    case 0x00:
    case 0x01: xcdr = 1; break;
    case 0x06:
    case 0x07: xcdr = 2; break;
    default: return bad(ErrorCode::kMalformed, topic, "a representation these final types are not sent in");
  }
  const bool bswap = ((bytes[1] & 1) != 0) != kHostLittleEndian;
  const std::uint32_t pad = ((std::uint32_t{bytes[2]} << 8) | bytes[3]) & 2;  // as Cyclone 0.10 reads it
  const std::size_t body = bytes.size() - 4;
  if (body > kCdrSizeMax) return bad(ErrorCode::kTooLarge, topic, "too large");
  if (body < pad) return bad(ErrorCode::kMalformed, topic, "padding longer than the body");
  // Normalizing swaps bytes in place and loads through aligned pointers: a private, aligned copy.
  std::unique_ptr<char, void (*)(void*)> buf(static_cast<char*>(std::malloc(body + kSlack)), std::free);
  if (!buf) return bad(ErrorCode::kTooLarge, topic, "out of memory");
  if (body > 0) std::memcpy(buf.get(), bytes.data() + 4, body);
  std::memset(buf.get() + body, 0, kSlack);
  std::uint32_t used = 0;
  const auto size = static_cast<std::uint32_t>(body - pad);
  if (dds_stream_normalize_data(buf.get(), &used, size, bswap, xcdr, desc.m_ops) == nullptr)
    return bad(ErrorCode::kMalformed, topic, "the body does not follow the type");
  if (used > size) return bad(ErrorCode::kMalformed, topic, "a field runs past the end of the body");
  std::unique_ptr<void, void (*)(void*)> sample(std::calloc(1, desc.m_size), std::free);
  if (!sample) return bad(ErrorCode::kTooLarge, topic, "out of memory");
  dds_istream_t is;
  dds_istream_init(&is, used, buf.get(), xcdr);
  (void)dds_stream_read(&is, static_cast<char*>(sample.get()), desc.m_ops);
  dds_istream_fini(&is);
  Sample e = wire::sample_of(topic, sample.get());
  dds_stream_free_sample(sample.get(), desc.m_ops);
  return e;
}

CdrSample encode_cdr_sample(const Sample& s, int xcdr_version, bool little_endian) {
  wire::SampleBuilder b;
  auto [topic, sample] = b.build(s.message, s.from, s.to);
  const dds_topic_descriptor_t& desc = wire::descriptor(topic);
  const auto xcdr = static_cast<std::uint32_t>(xcdr_version == 2 ? 2 : 1);
  dds_ostream_t os;
  dds_ostream_init(&os, 0, xcdr);
  (void)dds_stream_write_with_byte_order(&os, static_cast<const char*>(sample), desc.m_ops,
                                         little_endian ? DDSRT_BOSEL_LE : DDSRT_BOSEL_BE);
  const std::uint32_t len = os.m_index, pad = (4 - (len & 3)) & 3;  // a multiple of 4, as DDSI sends
  CdrSample out{topic, std::vector<std::uint8_t>(4 + len + pad, 0)};
  out.bytes[1] = static_cast<std::uint8_t>((xcdr == 2 ? 0x06 : 0x00) | (little_endian ? 1 : 0));
  out.bytes[3] = static_cast<std::uint8_t>(pad);
  if (len > 0) std::memcpy(out.bytes.data() + 4, os.m_buffer, len);
  dds_ostream_fini(&os);
  return out;
}

void deliver_cdr_sample(Replicator& r, DdsTopic topic, std::span<const std::uint8_t> bytes, std::int64_t now_ns) {
  auto s = decode_cdr_sample(topic, bytes);
  if (s.ok()) r.on_sample(*s, now_ns);
  else r.on_undecodable(s.error());
}

}  // namespace quiver::agents
