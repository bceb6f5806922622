#pragma once
// Private: the protocol's messages as IDL samples and back, in one place. The transport, the
// domain-free CDR codec (fuzzers) and nothing else use these. Received samples become envelopes
// exactly as they arrived: validate() (replication/validate.h) judges them, for every transport.

#include <dds/dds.h>

#include <array>
#include <memory>
#include <vector>

#include "quiver/agents/transport/wire/cdr_sample.h"
#include "quiver/agents/replica/replication/messages.h"
#include "quiver_wire.h"

namespace quiver::agents::inline transport::dds_samples {

const dds_topic_descriptor_t& descriptor(DdsTopic t);

inline quiver_wire_Replica to_wire(const PeerId& p) { return quiver_wire_Replica{p.agent, p.incarnation}; }
inline PeerId from_wire(const quiver_wire_Replica& r) { return PeerId{r.agent, r.incarnation}; }

// Received samples -> envelopes (the destination is kept: the caller filters).
Envelope envelope_of(const quiver_wire_Summary& s);
Envelope envelope_of(const quiver_wire_Delta& s);
Envelope envelope_of(const quiver_wire_Pull& s);
Envelope envelope_of(const quiver_wire_StateChunk& s);
Envelope envelope_of(const quiver_wire_Bye& s);
/// The envelope of a sample of `t` (a pointer to the type of that topic).
Envelope envelope_of(DdsTopic t, const void* sample);

/// Builds the sample of one message. The sample points into the message (strings, payloads) and
/// into this builder's arrays, which are reused: after the first few, building allocates nothing.
/// Valid until the next build() or the message goes.
class SampleBuilder {
 public:
  /// @returns the topic and the sample to write.
  std::pair<DdsTopic, const void*> build(const Message& m, const PeerId& sender, const PeerId& destination);

 private:
  struct Ranges {
    std::vector<quiver_wire_ReplicaRanges> replicas;
    std::vector<quiver_wire_SeqRange> flat;
    std::vector<std::size_t> starts;
    dds_sequence_quiver_wire_ReplicaRanges build(const RangeList& r);
  };
  Ranges a_, b_;
  quiver_wire_Summary summary_{};
  quiver_wire_Delta delta_{};
  quiver_wire_Pull pull_{};
  quiver_wire_StateChunk state_{};
  quiver_wire_Bye bye_{};
};

}  // namespace quiver::agents::inline transport::dds_samples
