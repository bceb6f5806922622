// The protocol's messages as IDL samples and back, in one place, for the DDS transport and the CDR codec.
#include "samples.h"

#include <type_traits>

namespace quiver::agents::inline transport::wire {
namespace {

// Summary.role's bits.
// The bits above them carry a gateway's generation (modulo 64).
constexpr std::uint8_t kRoleObserver = 1, kRoleGateway = 2, kRoleGenerationShift = 2;

void read_ranges(const dds_sequence_quiver_wire_ReplicaRanges& in, RangeList& out) {
  out.clear();
  for (std::uint32_t i = 0; i < in._length; ++i) {
    const auto& rr = in._buffer[i];
    const PeerId r = from_wire(rr.replica);
    for (std::uint32_t j = 0; j < rr.ranges._length; ++j)
      out.push_back(Range{r, rr.ranges._buffer[j].lo, rr.ranges._buffer[j].hi});
  }
}

dds_sequence_octet octets(const std::vector<std::uint8_t>& v) {
  dds_sequence_octet s{};
  s._length = s._maximum = static_cast<std::uint32_t>(v.size());
  s._buffer = const_cast<std::uint8_t*>(v.data());
  s._release = false;
  return s;
}

std::shared_ptr<const std::vector<std::uint8_t>> copy_octets(const dds_sequence_octet& s) {
  return std::make_shared<const std::vector<std::uint8_t>>(s._buffer, s._buffer + s._length);
}

template <class T>
Sample addressed(const T& s, Message m) {
  return Sample{from_wire(s.sender), from_wire(s.destination), std::move(m)};
}

}  // namespace

const dds_topic_descriptor_t& descriptor(DdsTopic t) {
  static const std::array<const dds_topic_descriptor_t*, kDdsTopicCount> kDescs = {
      &quiver_wire_Summary_desc, &quiver_wire_Delta_desc, &quiver_wire_Pull_desc, &quiver_wire_StateChunk_desc,
      &quiver_wire_Bye_desc};
  return *kDescs[static_cast<std::size_t>(t)];
}

Sample sample_of(const quiver_wire_Summary& s) {
  SummaryMsg m;
  m.name = s.name ? s.name : "";
  m.observer = (s.role & kRoleObserver) != 0;
  m.gateway = (s.role & kRoleGateway) != 0;
  m.generation = static_cast<std::uint8_t>(s.role >> kRoleGenerationShift);
  m.digest = s.digest;
  m.beat = static_cast<Beat>(s.beat);  // validate() refuses a beat out of range
  m.life = s.life;
  m.set_hash = s.set_hash;
  m.count = s.count;
  m.your_seq = s.your_seq;
  m.covered = s.covered;
  m.subject = from_wire(s.subject);
  read_ranges(s.applied, m.applied);
  m.rumors.reserve(s.rumors._length);
  std::uint32_t first = 0;
  // A hold beat's number rides as its first rumor (quiver_wire.idl); one that names another
  // replica leaves subject_seq 0, which validate() refuses.
  if ((m.beat == Beat::kHoldQuery || m.beat == Beat::kHolds) && s.rumors._length > 0) {
    first = 1;
    if (from_wire(s.rumors._buffer[0].peer) == m.subject) m.subject_seq = s.rumors._buffer[0].life;
  }
  for (std::uint32_t i = first; i < s.rumors._length; ++i) {
    const auto& r = s.rumors._buffer[i];
    m.rumors.push_back(Rumor{from_wire(r.peer), r.life, static_cast<Liveness>(r.status)});
  }
  return Sample{PeerId{s.sender_agent, s.sender_incarnation}, from_wire(s.destination), std::move(m)};
}

Sample sample_of(const quiver_wire_Delta& s) {
  DeltaMsg m{from_wire(s.origin), s.lo, s.hi, copy_octets(s.payload), nullptr};
  if (s.signature._length > 0) m.signature = copy_octets(s.signature);
  return addressed(s, std::move(m));
}

Sample sample_of(const quiver_wire_Pull& s) {
  PullMsg m;
  m.request = s.request;
  read_ranges(s.applied, m.applied);
  read_ranges(s.context, m.context);
  m.whole_state = s.whole_state;
  m.as_state = s.as_state;
  return addressed(s, std::move(m));
}

Sample sample_of(const quiver_wire_StateChunk& s) {
  StateMsg m;
  m.request = s.request;
  m.index = s.index;
  m.count = s.count;
  read_ranges(s.applied, m.applied);
  m.chunk = copy_octets(s.payload);
  return addressed(s, std::move(m));
}

Sample sample_of(const quiver_wire_Bye& s) {
  return Sample{from_wire(s.sender), PeerId{}, ByeMsg{}};
}

Sample sample_of(DdsTopic t, const void* p) {
  switch (t) {
    case DdsTopic::kSummary: return sample_of(*static_cast<const quiver_wire_Summary*>(p));
    case DdsTopic::kDelta: return sample_of(*static_cast<const quiver_wire_Delta*>(p));
    case DdsTopic::kPull: return sample_of(*static_cast<const quiver_wire_Pull*>(p));
    case DdsTopic::kState: return sample_of(*static_cast<const quiver_wire_StateChunk*>(p));
    case DdsTopic::kBye: break;
  }
  return sample_of(*static_cast<const quiver_wire_Bye*>(p));
}

dds_sequence_quiver_wire_ReplicaRanges SampleBuilder::Ranges::build(const RangeList& c) {
  replicas.clear();
  flat.clear();
  starts.clear();
  for (const Range& x : c) {
    if (replicas.empty() || !(from_wire(replicas.back().replica) == x.replica)) {
      replicas.push_back(quiver_wire_ReplicaRanges{to_wire(x.replica), {}});
      starts.push_back(flat.size());
    }
    flat.push_back(quiver_wire_SeqRange{x.lo, x.hi});
  }
  for (std::size_t i = 0; i < replicas.size(); ++i) {  // `flat` is final now: point into it
    const std::size_t end = i + 1 < starts.size() ? starts[i + 1] : flat.size();
    auto& s = replicas[i].ranges;
    s._length = s._maximum = static_cast<std::uint32_t>(end - starts[i]);
    s._buffer = flat.data() + starts[i];
    s._release = false;
  }
  dds_sequence_quiver_wire_ReplicaRanges out{};
  out._length = out._maximum = static_cast<std::uint32_t>(replicas.size());
  out._buffer = replicas.data();
  out._release = false;
  return out;
}

std::pair<DdsTopic, const void*> SampleBuilder::build(const Message& m, const PeerId& sender,
                                                      const PeerId& destination) {
  const quiver_wire_Replica from = to_wire(sender), to = to_wire(destination);
  return std::visit(
      [&](const auto& msg) -> std::pair<DdsTopic, const void*> {
        using T = std::decay_t<decltype(msg)>;
        if constexpr (std::is_same_v<T, SummaryMsg>) {
          summary_ = quiver_wire_Summary{};
          summary_.sender_agent = sender.agent;
          summary_.sender_incarnation = sender.incarnation;
          summary_.name = const_cast<char*>(msg.name.c_str());
          summary_.role = static_cast<std::uint8_t>((msg.observer ? kRoleObserver : 0) | (msg.gateway ? kRoleGateway : 0) |
                                                    ((msg.generation & 63) << kRoleGenerationShift));
          summary_.applied = a_.build(msg.applied);
          summary_.digest = msg.digest;
          summary_.destination = to;
          summary_.beat = static_cast<std::uint8_t>(msg.beat);
          summary_.life = msg.life;
          summary_.set_hash = msg.set_hash;
          summary_.count = msg.count;
          summary_.your_seq = msg.your_seq;
          summary_.covered = msg.covered;
          summary_.subject = to_wire(msg.subject);
          rumors_.clear();
          if (msg.beat == Beat::kHoldQuery || msg.beat == Beat::kHolds)
            rumors_.push_back(quiver_wire_Rumor{to_wire(msg.subject), msg.subject_seq, 0});
          for (const Rumor& r : msg.rumors)
            rumors_.push_back(quiver_wire_Rumor{to_wire(r.peer), r.life, static_cast<std::uint8_t>(r.status)});
          summary_.rumors._length = summary_.rumors._maximum = static_cast<std::uint32_t>(rumors_.size());
          summary_.rumors._buffer = rumors_.data();
          summary_.rumors._release = false;
          return {DdsTopic::kSummary, &summary_};
        } else if constexpr (std::is_same_v<T, DeltaMsg>) {
          delta_ = quiver_wire_Delta{from, to, to_wire(msg.origin), msg.lo, msg.hi, octets(*msg.payload),
                                     msg.signature ? octets(*msg.signature) : dds_sequence_octet{}};
          return {DdsTopic::kDelta, &delta_};
        } else if constexpr (std::is_same_v<T, PullMsg>) {
          pull_ = quiver_wire_Pull{from, to, msg.request, a_.build(msg.applied), b_.build(msg.context), msg.whole_state,
                                   msg.as_state};
          return {DdsTopic::kPull, &pull_};
        } else if constexpr (std::is_same_v<T, StateMsg>) {
          state_ = quiver_wire_StateChunk{from,
                                          to,
                                          msg.request,
                                          static_cast<std::uint32_t>(msg.index),
                                          static_cast<std::uint32_t>(msg.count),
                                          a_.build(msg.applied),
                                          octets(*msg.chunk)};
          return {DdsTopic::kState, &state_};
        } else {
          bye_ = quiver_wire_Bye{from};
          return {DdsTopic::kBye, &bye_};
        }
      },
      m);
}

}  // namespace quiver::agents::inline transport::wire
