#pragma once
// Private: the protocol's messages as IDL samples and back, in one place. The DDS transport and
// the CDR codec (cdr_sample.h: the simulator, the fuzzers) use these. Received samples become
// Samples exactly as they arrived: validate() (replication/validate.h) judges them, for every
// transport.

#include <dds/dds.h>

#include <array>
#include <memory>
#include <vector>

#include "quiver/agents/transport/wire/cdr_sample.h"
#include "quiver/agents/replica/replication/messages.h"
#include "quiver_wire.h"

namespace quiver::agents::inline transport::wire {

const dds_topic_descriptor_t& descriptor(DdsTopic t);

inline quiver_wire_Replica to_wire(const PeerId& p) { return quiver_wire_Replica{p.agent, p.incarnation}; }
inline PeerId from_wire(const quiver_wire_Replica& r) { return PeerId{r.agent, r.incarnation}; }

// Received IDL samples -> Samples (the destination is kept: the caller filters).
Sample sample_of(const quiver_wire_Summary& s);
Sample sample_of(const quiver_wire_Delta& s);
Sample sample_of(const quiver_wire_Pull& s);
Sample sample_of(const quiver_wire_StateChunk& s);
Sample sample_of(const quiver_wire_Bye& s);
/// The Sample of an IDL sample of `t` (a pointer to the type of that topic).
Sample sample_of(DdsTopic t, const void* sample);

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
  std::vector<quiver_wire_Rumor> rumors_;
  quiver_wire_Summary summary_{};
  quiver_wire_Delta delta_{};
  quiver_wire_Pull pull_{};
  quiver_wire_StateChunk state_{};
  quiver_wire_Bye bye_{};
};

}  // namespace quiver::agents::inline transport::wire
