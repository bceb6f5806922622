// The one check of every sample a peer sends, whatever carried it: well-formed and within limits, or refused whole
// with the sender, message, field and value named.
#include "quiver/agents/replica/replication/validate.h"

#include <string>
#include <type_traits>

#include "quiver/crdt/dot.h"
#include "quiver/graph/limits.h"

namespace quiver::agents::inline replica {
namespace {

std::string num(std::uint64_t v) { return std::to_string(v); }

Status ranges(const RangeList& r, const char* field, const SampleLimits& lim) {
  if (r.size() > lim.max_ranges)
    return make_error(ErrorCode::kTooLarge, std::string(field) + " holds " + num(r.size()) + " ranges (the limit is " +
                                                num(lim.max_ranges) + ")");
  for (const Range& x : r) {
    if (x.replica.is_null()) return make_error(ErrorCode::kMalformed, std::string(field) + " names the null replica");
    if (x.lo == 0 || x.hi < x.lo || x.hi > crdt::kMaxCounter)
      return make_error(ErrorCode::kMalformed, std::string(field) + " holds the range [" + num(x.lo) + ", " + num(x.hi) +
                                                   "] of " + x.replica.to_string() +
                                                   " (need 1 <= lo <= hi <= 2^53-1)");
  }
  return {};
}

template <class Bytes>
Status bytes(const Bytes& b, const char* field, std::size_t max) {
  if (!b || b->empty()) return make_error(ErrorCode::kMalformed, std::string(field) + " is empty");
  if (b->size() > max)
    return make_error(ErrorCode::kTooLarge,
                      std::string(field) + " is " + num(b->size()) + " bytes (the limit is " + num(max) + ")");
  return {};
}

Status check(const SummaryMsg& m, const SampleLimits& lim) {
  if (m.name.size() > lim.max_name_bytes)
    return make_error(ErrorCode::kTooLarge, "the agent name is " + num(m.name.size()) + " bytes (the limit is " +
                                                num(lim.max_name_bytes) + ")");
  if (!graph::valid_utf8(m.name)) return make_error(ErrorCode::kMalformed, "the agent name is not UTF-8");
  if (static_cast<std::uint8_t>(m.beat) >= kBeatCount)
    return make_error(ErrorCode::kMalformed, "its beat is " + num(static_cast<std::uint8_t>(m.beat)) + " (known: 0 to " +
                                                 num(kBeatCount - 1) + ")");
  if (m.beat != Beat::kFull && !m.applied.empty())
    return make_error(ErrorCode::kMalformed, "a beat that is not a full summary carries an applied set");
  if (m.beat == Beat::kPingReq && m.subject.is_null())
    return make_error(ErrorCode::kMalformed, "a ping request names no replica to probe");
  if ((m.beat == Beat::kHoldQuery || m.beat == Beat::kHolds) && (m.subject.is_null() || m.subject_seq == 0))
    return make_error(ErrorCode::kMalformed, "a hold query or answer names no replica or no sequence number");
  if (m.beat == Beat::kBehind && !m.gateway)
    return make_error(ErrorCode::kMalformed, "a list of members behind a gateway from a replica that is no gateway");
  if (m.rumors.size() > lim.max_rumors)
    return make_error(ErrorCode::kTooLarge, "it carries " + num(m.rumors.size()) + " rumors (the limit is " +
                                                num(lim.max_rumors) + ")");
  for (const Rumor& r : m.rumors) {
    if (r.peer.is_null()) return make_error(ErrorCode::kMalformed, "a rumor names the null replica");
    if (static_cast<std::uint8_t>(r.status) > 2 || (m.beat == Beat::kBehind && r.status == Liveness::kSuspect))
      return make_error(ErrorCode::kMalformed, "a rumor about " + r.peer.to_string() + " has the status " +
                                                   num(static_cast<std::uint8_t>(r.status)) +
                                                   (m.beat == Beat::kBehind ? " (known behind a gateway: 0, 2)" : " (known: 0 to 2)"));
  }
  return ranges(m.applied, "its applied set", lim);
}

Status check(const DeltaMsg& m, const SampleLimits& lim) {
  if (m.origin.is_null()) return make_error(ErrorCode::kMalformed, "the origin is null");
  if (m.lo == 0 || m.hi < m.lo || m.hi > crdt::kMaxCounter)
    return make_error(ErrorCode::kMalformed, "the sequence numbers [" + num(m.lo) + ", " + num(m.hi) + "] of " +
                                                 m.origin.to_string() + " are invalid");
  if (m.hi - m.lo >= lim.max_interval)
    return make_error(ErrorCode::kTooLarge, "the interval of " + m.origin.to_string() + " claims " +
                                                num(m.hi - m.lo + 1) + " sequence numbers (the limit is " +
                                                num(lim.max_interval) + ")");
  if (m.signature && m.signature->size() > lim.max_signature_bytes)
    return make_error(ErrorCode::kTooLarge, "the signature of " + m.origin.to_string() + "'s delta holds " +
                                                num(m.signature->size()) + " bytes (the limit is " +
                                                num(lim.max_signature_bytes) + ")");
  return bytes(m.payload, "the payload", lim.max_payload_bytes);
}

Status check(const PullMsg& m, const SampleLimits& lim) {
  if (Status s = ranges(m.applied, "its applied set", lim); !s.ok()) return s;
  return ranges(m.context, "its context", lim);
}

Status check(const StateMsg& m, const SampleLimits& lim) {
  if (m.count == 0 || m.count > lim.max_chunks)
    return make_error(ErrorCode::kTooLarge, "it announces " + num(m.count) + " chunks (the limit is " +
                                                num(lim.max_chunks) + ")");
  if (m.index >= m.count)
    return make_error(ErrorCode::kMalformed, "chunk " + num(m.index) + " of " + num(m.count) + " is out of range");
  if (Status s = ranges(m.applied, "its applied set", lim); !s.ok()) return s;
  return bytes(m.chunk, "the chunk", lim.max_chunk_bytes);
}

Status check(const ByeMsg&, const SampleLimits&) { return {}; }

}  // namespace

Status validate(const Sample& s, const SampleLimits& lim, const std::function<std::string(const PeerId&)>& who) {
  if (s.from.is_null()) return make_error(ErrorCode::kMalformed, "a sample from the null replica");
  Status st = std::visit([&](const auto& msg) { return check(msg, lim); }, s.message);
  if (!st.ok())
    return make_error(st.error().code,
                      "from " + (who ? who(s.from) : s.from.to_string()) + ": " + message_kind(s.message) + ": " +
                          st.error().message);
  return {};
}

}  // namespace quiver::agents
