#pragma once
/// @file
/// The replication protocol's messages, independent of how a transport carries them: the
/// simulator encodes them as byte frames (frame_codec.h), the DDS transport as IDL types in CDR.

#include <cstdint>
#include <memory>
#include <string>
#include <variant>
#include <vector>

#include "quiver/agents/replication/transport.h"
#include "quiver/crdt/causal_context.h"

namespace quiver::agents {

/// Heartbeat: who I am and which (origin, seq) I hold. Acknowledgement and liveness at once.
struct SummaryMsg {
  std::string name;
  bool observer = false;
  crdt::CausalContext applied;
};

/// One delta interval of one origin: sequence numbers [lo, hi], encoded graph delta.
struct DeltaMsg {
  PeerId origin;
  std::uint64_t lo = 0;
  std::uint64_t hi = 0;
  std::shared_ptr<const std::vector<std::uint8_t>> payload;
};

/// "Send me what I lack": my (origin, seq) set and my causal context (for a context diff).
struct PullMsg {
  std::uint64_t request = 0;
  crdt::CausalContext applied;
  crdt::CausalContext context;
};

/// One chunk of a state transfer (an encoded context diff split into `count` chunks).
struct StateMsg {
  std::uint64_t request = 0;
  std::uint32_t index = 0;
  std::uint32_t count = 1;
  crdt::CausalContext applied;  ///< the sender's (origin, seq) set; meaningful in chunk 0
  std::shared_ptr<const std::vector<std::uint8_t>> chunk;
};

/// The sender leaves cleanly.
struct ByeMsg {};

using Message = std::variant<SummaryMsg, DeltaMsg, PullMsg, StateMsg, ByeMsg>;

/// Messages from one replica to one (or every, when `to` is null) other.
struct Envelope {
  PeerId from;
  PeerId to;
  std::vector<Message> messages;
};

/// Approximate wire size of a message (for batching decisions).
std::size_t approx_size(const Message& m);

}  // namespace quiver::agents
