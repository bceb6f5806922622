#pragma once
/// @file
/// What a Replicator (replicator.h) is built with: its name and role, the protocol's periods,
/// bounds and limits, and the membership it runs (gossip or all-to-all). docs/protocol.md says
/// what each one is for.

#include <cstddef>
#include <cstdint>
#include <string>

#include "quiver/agents/replica/replication/validate.h"

namespace quiver::agents::inline replica {

struct ReplicatorOptions {
  std::string name;                          ///< the agent's name, announced to peers
  bool observer = false;                     ///< announce as a read-only observer
  std::int64_t heartbeat_ns = 100'000'000;   ///< summary period
  std::int64_t lease_ns = 1'000'000'000;     ///< a peer silent this long has left
  std::int64_t pull_timeout_ns = 400'000'000;  ///< longest silence a pull waits (first tries wait less)
  std::int64_t pull_first_timeout_ns = 50'000'000;  ///< the first try's patience; doubles per timeout
  std::int64_t gap_grace_ns = 30'000'000;    ///< reordering tolerated before a gap is pulled
  /// Gossip: a peer whose set hash differed from ours in kStaleReports reports in a row is pulled
  /// from, whatever the counts say, at most once per this period or two probe rounds (probe_ns x
  /// live peers x 2), whichever is longer (0: never). The counts miss a change only a peer holds
  /// while changes keep arriving (docs/protocol.md). Off by default for now: with 2 s it left
  /// some of dds_scale_test's 32 members 10 to 40 s late at the end (not yet explained).
  std::int64_t stale_pull_ns = 0;
  std::size_t buffer_bytes = 16u << 20;      ///< relay buffer of recent deltas (all origins)
  std::size_t chunk_bytes = 256u << 10;      ///< state transfer chunk size
  /// A pull that the relay buffer would answer with more deltas than this is answered with a
  /// state (a context diff): a joiner of a long history gets what is there, not every change.
  std::size_t max_relayed_answer = 256;
  std::size_t max_state_bytes = 1u << 30;    ///< a state transfer larger than this is refused
  bool coalesce = false;                     ///< hold local deltas until flush() or tick()
  SampleLimits limits;                       ///< what one sample may hold (validate.h)
  std::size_t max_peers = 1024;              ///< peers remembered at once (live or recently gone; at most 65,535)
  std::size_t max_peer_ranges = 1u << 20;    ///< ranges of all peers' summaries kept together
  /// Versions of one (origin, seq) remembered and relayed; later ones are joined but not relayed
  /// (the periodic state digest repairs replicas that missed them).
  std::size_t max_versions = 64;
  int suspect_after_timeouts = 6;            ///< pulls in a row a talking peer leaves unanswered before...
  std::int64_t suspect_ns = 3'000'000'000;   ///< ...its summaries are ignored this long
  /// A summary carries the state digest this often (0: never). A peer that holds the same
  /// (origin, seq) set with another digest twice in a row is asked for its whole state.
  std::int64_t digest_every_ns = 1'000'000'000;
  /// A sampling observer (0: off): it reads no deltas (its transport subscribes to none, so no
  /// writer sends it any) and instead pulls what it lacks as one context diff, at most this often.
  /// For a viewer: writers pay nothing per change for it.
  std::int64_t sample_ns = 0;
  /// A sampling observer's demand on the peers that answer it (0: none): after a diff of B
  /// bytes it waits at least B / sample_bytes_per_s before its next pull, so that a viewer of a
  /// busy graph samples less often instead of making the writers serialise more.
  std::size_t sample_bytes_per_s = 0;
  /// Membership and anti-entropy by gossip over partial views instead of all-to-all summaries
  /// (docs/protocol.md, "Membership and anti-entropy without all-to-all heartbeats"): every
  /// probe_ns a replica probes one peer with a constant-size beat (SWIM-style, with indirect
  /// probes and suspicion), membership news rides on the beats, and the (origin, seq) sets are
  /// compared by hash and count, exchanged only when they differ. A transport that delivers
  /// unicast samples to their destination only (the simulator's network) makes each replica's
  /// cost independent of the number of replicas. The default; off: all-to-all summaries (every
  /// heartbeat, the whole (origin, seq) set to every peer; docs/protocol.md).
  bool gossip = true;
  std::int64_t probe_ns = 250'000'000;       ///< gossip: one probe per period
  int indirect_probes = 3;                    ///< gossip: peers asked to probe an unanswering one
  /// gossip: a peer suspected this long without refuting is declared gone (0: max(lease_ns, 3 probe_ns)).
  std::int64_t suspect_timeout_ns = 0;
  int rumor_repeats = 3;                      ///< gossip: each rumor is sent this many times log2(peers + 1)
  std::size_t rumors_per_beat = 6;            ///< gossip: rumors piggybacked on one beat
  /// gossip: every period one replica in about (live peers + 1) says hello to everyone again,
  /// and a replica that hears nobody always does (rediscovery after partitions and restarts).
  std::int64_t rediscover_ns = 2'000'000'000;
  /// gossip: deltas of other origins leave the relay buffer after this long (own deltas once
  /// every live peer acknowledged them), whatever its byte bound would allow.
  std::int64_t relay_retain_ns = 2'000'000'000;
  /// gossip: how many members answer a hello, on average (0: every member that did not know the
  /// sender, or 3 once the transport introduced a peer). A transport that introduces peers itself
  /// (introduce(), e.g. DDS discovery) needs only a few: one answer tells a newcomer the hash of a
  /// set to pull. Then a replica that knows live peers says hello to that many of them, chosen
  /// at random, instead of to everyone; each answers.
  int hello_answers = 0;
  /// One side of a robot team's gateway (bridge.h, docs/teams.md): it vouches for the replicas
  /// behind it (on the bridge's other side). Its acknowledgement of a claim (kHolds) means every
  /// one of them holds the claim too, and it tells its peers which of them are alive (kBehind),
  /// so that a lock held behind it neither looks expired nor is granted twice. Needs gossip.
  bool gateway = false;
  /// A gateway's: the robot it serves (the team file's name). Its kBehind beats carry it, and
  /// the robot and name of each replica they list, so that every replica of the team knows which
  /// robot and which agent each origin is (Replicator::robot_of()).
  std::string robot;
};

}  // namespace quiver::agents
