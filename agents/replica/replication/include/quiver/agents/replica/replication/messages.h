#pragma once
/// @file
/// The replication protocol's messages, independent of how a transport carries them. Every
/// transport carries them the same way: one message is one sample of its kind's IDL type
/// (agents/transport/wire), encoded in CDR by Cyclone's serializer, whether Cyclone DDS ships it or
/// the simulator does.
///
/// Messages hold what arrived, unchecked: transports fill them and hand them to
/// Replicator::on_sample(), which checks every sample in one place (validate.h) before any of it
/// is used. Sets of (replica, counter) pairs travel as range lists for that reason: a
/// CausalContext would normalise away what was wrong with them.

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <variant>
#include <vector>

#include "quiver/agents/replica/replication/transport.h"
#include "quiver/crdt/causal_context.h"

namespace quiver::agents::inline replica {

/// One range [lo, hi] of counters (or sequence numbers) of one replica.
struct Range {
  PeerId replica;
  std::uint64_t lo = 0;
  std::uint64_t hi = 0;
  friend bool operator==(const Range&, const Range&) = default;
};
/// A set of (replica, counter) pairs as ranges, as a transport carried it.
using RangeList = std::vector<Range>;

/// The canonical ranges of a context (replicas ascending, ranges ascending and disjoint).
/// Thread-safe.
/// @returns one Range per maximal range of `c`, as CausalContext::for_each_range() yields them.
RangeList to_ranges(const crdt::CausalContext& c);
/// The context of checked ranges (validate() first: lo >= 1, lo <= hi).
/// @pre every range passed validate(); an unchecked one is normalised (lo 0 read as 1, hi < lo
///      dropped), hiding the fault. Thread-safe.
/// @returns the union of the ranges.
crdt::CausalContext to_context(const RangeList& r);

/// What a summary is for. kFull carries the sender's whole (origin, seq) set (`applied`); the
/// others are the constant-size beats of the gossip membership (docs/protocol.md, "Membership
/// and anti-entropy without all-to-all heartbeats"): they carry a hash and a count of that set
/// instead, and membership news (`rumors`).
enum class Beat : std::uint8_t {
  kFull = 0,       ///< the whole (origin, seq) set: to everyone (legacy heartbeat, hand-over offer)
  kHello = 1,      ///< a replica starts: to everyone, once; members that were there answer kAck
  kPing = 2,       ///< a probe: answer kAck (to `subject` through the sender, when set)
  kAck = 3,        ///< a probe's answer (or an acknowledgement of a claim)
  kPingReq = 4,    ///< "probe `subject` for me": the receiver pings it and relays the answer
  kRelayedAck = 5,  ///< `subject` answered a probe made on the receiver's behalf
  // Robot teams (docs/teams.md): acknowledgements and liveness across a gateway.
  kHoldQuery = 6,  ///< "do you, and every replica behind you, hold `subject`'s 1..subject_seq?"
  kHolds = 7,      ///< "I, and every replica behind me, hold `subject`'s 1..subject_seq"
  kBehind = 8      ///< from a gateway: the replicas in `rumors` are alive (or gone) behind it
};
inline constexpr std::uint8_t kBeatCount = 9;

/// What one replica says about another's membership (SWIM-style): the peer, the life
/// (incarnation of its liveness, raised by the peer itself to refute a suspicion) and the status.
enum class Liveness : std::uint8_t { kAlive = 0, kSuspect = 1, kDead = 2 };
struct Rumor {
  PeerId peer;
  std::uint64_t life = 0;
  Liveness status = Liveness::kAlive;
  friend bool operator==(const Rumor&, const Rumor&) = default;
};

/// Heartbeat: who I am and which (origin, seq) I hold. Acknowledgement and liveness at once.
struct SummaryMsg {
  std::string name;
  bool observer = false;
  /// kFull: the (origin, seq) set held. Empty in the other beats.
  RangeList applied;
  /// The sender's graph digest (64 of its 128 bits) when it holds exactly `applied`; 0: not sent.
  /// Equal `applied` sets with different digests mean the replicas joined different payloads
  /// under the same numbers (an equivocation): they repair by exchanging whole states.
  std::uint64_t digest = 0;
  Beat beat = Beat::kFull;
  std::uint64_t life = 0;      ///< the sender's life (Rumor::life)
  std::uint64_t set_hash = 0;  ///< a hash of the sender's (origin, seq) set (0: not sent)
  std::uint64_t count = 0;     ///< how many (origin, seq) pairs the sender holds
  /// Addressed beats: the greatest n such that the sender holds the receiver's own 1..n.
  std::uint64_t your_seq = 0;
  /// Addressed beats: the set hash of the receiver's last kFull that the sender holds all of (0: none).
  std::uint64_t covered = 0;
  PeerId subject;              ///< kPingReq, kPing, kAck, kRelayedAck, kHoldQuery, kHolds: the third replica (see Beat)
  /// kHoldQuery: the sequence number wanted of `subject`; kHolds: held (on the wire, the first
  /// rumor carries it: quiver_wire.idl).
  std::uint64_t subject_seq = 0;
  std::vector<Rumor> rumors;   ///< membership news, piggybacked
  bool gateway = false;  ///< the sender is one side of a gateway (bridge.h): it vouches for replicas behind it
  /// A gateway's: raised (modulo 64) whenever replicas came behind it; what it vouched for under
  /// an older one does not cover them (docs/teams.md).
  std::uint8_t generation = 0;
};

/// One delta interval of one origin: sequence numbers [lo, hi], encoded graph delta (whose
/// payload names the same interval).
struct DeltaMsg {
  PeerId origin;
  std::uint64_t lo = 0;
  std::uint64_t hi = 0;
  std::shared_ptr<const std::vector<std::uint8_t>> payload;
  /// The origin's signature of `payload` when the replicas run with identities (admission.h);
  /// null or empty: unsigned. Relays pass it on unchanged.
  std::shared_ptr<const std::vector<std::uint8_t>> signature;
};

/// "Send me what I lack": my (origin, seq) set and my causal context (for a context diff).
struct PullMsg {
  std::uint64_t request = 0;
  RangeList applied;
  RangeList context;
  bool whole_state = false;  ///< answer with the whole state, not deltas or a context diff
  bool as_state = false;     ///< answer with a context diff even if recent deltas would do
};

/// One chunk of a state transfer (an encoded context diff split into `count` chunks), answering
/// the pull `request`.
struct StateMsg {
  std::uint64_t request = 0;
  std::uint64_t index = 0;
  std::uint64_t count = 1;
  RangeList applied;  ///< the sender's (origin, seq) set; meaningful in chunk 0
  std::shared_ptr<const std::vector<std::uint8_t>> chunk;
};

/// The sender leaves cleanly.
struct ByeMsg {};

using Message = std::variant<SummaryMsg, DeltaMsg, PullMsg, StateMsg, ByeMsg>;

/// One message from one replica to one other (or to every other, when `to` is null): what one
/// DDS sample carries.
struct Sample {
  PeerId from;
  PeerId to;
  Message message;
  /// The participant that sent it, as the receiving transport authenticated it: a DDS Security
  /// participant's GUID, which IdentityBook::authenticates() binds to an agent's certificate
  /// (docs/security.md, "The fast path"). All zero when the transport authenticates nobody
  /// (plain DDS, the simulator, a gateway's bridge) or its governance does not authenticate
  /// origins. Not on the wire: the `from` above is only what the sample claims.
  std::array<std::uint8_t, 16> sender{};
};

/// "summary", "delta", "pull", "state", "bye".
/// @returns the static name of `m`'s alternative. Thread-safe.
/// @pre `m` is not valueless_by_exception().
const char* message_kind(const Message& m);

}  // namespace quiver::agents
