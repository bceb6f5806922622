#pragma once
/// @file
/// The replication protocol: keeps one graph replica in step with its peers over any Transport.
///
///  - Every local commit becomes a delta numbered by a per-origin sequence number and is
///    broadcast at once (or coalesced into delta intervals when `coalesce` is set).
///  - Receivers join deltas in any order; they track which (origin, seq) they hold, and every
///    heartbeat broadcasts that set (a summary): it is both the acknowledgement and the
///    liveness signal.
///  - A replica that sees a peer holding changes it lacks (from a summary, or a gap in the
///    sequence numbers) pulls from that peer - any peer, not only the origin. The peer answers
///    with the missing deltas from its bounded relay buffer, or, if they were evicted, with a
///    context diff of its whole state (chunked). A pull that times out is retried elsewhere.
///  - Nothing blocks; time comes in through `now` arguments, so the simulator runs this exactly.
///
/// Hostile or broken peers (docs/protocol.md, "Bad input"): every sample is checked once
/// (validate.h) before use; a delta's payload must name the interval it claims and carry only its
/// origin's dots; the same (origin, seq) arriving with another payload is reported as an
/// equivocation (kEquivocation), and both payloads are joined (so replicas that got them in
/// either order converge), and so is a delta published under this replica's own name that it
/// never published (this replica's later deltas then take sequence numbers beyond it); state chunks are
/// accepted only in answer to this replica's own pull; the peer table, what each peer's summary
/// may hold, the relay buffer and the equivocation record are bounded; a peer whose summaries
/// claim changes it never delivers is ignored for a while; full-state answers to one peer are
/// rate-limited.
///
/// Threading: a Replicator and its Graph belong to one thread (the owner); only last_heartbeat()
/// may be called from any thread. Every callback it makes (membership, errors, the graph's
/// subscribers during a join, the Journal, the Admission, Transport::send) runs on the owner
/// thread, inside the call that caused it.
///
/// Errors: nothing here throws on bad input; what peers send wrong is counted (stats()) and
/// reported through on_error().

#include <cstdint>
#include <algorithm>
#include <functional>
#include <list>
#include <map>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

#include "quiver/agents/replica/replication/admission.h"
#include "quiver/agents/replica/replication/journal.h"
#include "quiver/agents/replica/replication/buffered_delta.h"
#include "quiver/agents/replica/replication/messages.h"
#include "quiver/agents/replica/replication/peer_table.h"
#include "quiver/agents/replica/replication/replicator_options.h"
#include "quiver/agents/replica/replication/transport.h"
#include "quiver/agents/replica/replication/validate.h"
#include "quiver/crdt/causal_context.h"
#include "quiver/graph/graph.h"
#include "quiver/base/hash.h"
#include "quiver/base/result.h"
#include "quiver/base/rng.h"

namespace quiver::agents::inline replica {

/// What a replica knows of a peer (peers(), the membership callbacks). With gossip, beyond the
/// peers it dealt with most recently a replica keeps no name, time or report of a peer
/// (peer_table.h): `name` is then the one its bounded name cache holds, or empty, and
/// `last_heard_ns` 0.
struct PeerInfo {
  PeerId id;
  std::string name;
  bool observer = false;
  bool gateway = false;  ///< one side of a gateway (ReplicatorOptions::gateway)
  bool alive = false;
  std::int64_t last_heard_ns = 0;  ///< 0: not recorded
  bool suspect = false;  ///< it claimed changes it did not deliver: its summaries are ignored for now
};

/// A replica alive behind a gateway: another robot's agent (docs/teams.md).
struct Member {
  PeerId id;
  std::string name;   ///< its agent name ("" not known)
  std::string robot;  ///< the robot it runs on, as its gateways said ("" not known)
  PeerId via;         ///< remote_members(): the gateway peer that lists it (null in members_here())
  friend bool operator==(const Member&, const Member&) = default;
};

enum class Membership : std::uint8_t { kJoined, kLeft };

struct ReplicatorStats {
  std::uint64_t samples_sent = 0, samples_received = 0;
  std::uint64_t deltas_published = 0, deltas_applied = 0, deltas_duplicate = 0, deltas_relayed = 0;
  std::uint64_t bytes_published = 0;  ///< the payloads of the deltas it published (encoded changes)
  std::uint64_t pulls_sent = 0, pulls_timed_out = 0, pulls_answered_with_deltas = 0, pulls_answered_with_state = 0;
  std::uint64_t states_applied = 0, state_bytes_received = 0;
  std::uint64_t rejected = 0;  ///< samples refused: undecodable, malformed, or messages that did not hold
  std::uint64_t buffer_evictions = 0;
  std::uint64_t equivocations = 0;        ///< (origin, seq) seen with two payloads, or forged under our name
  std::uint64_t states_unrequested = 0;   ///< state chunks that answered no pull of ours (dropped)
  std::uint64_t state_answers_throttled = 0;
  std::uint64_t peers_refused = 0;        ///< samples from new peers while the table was full
  std::uint64_t suspects = 0;             ///< peers found claiming what they did not deliver
  std::uint64_t divergences = 0;          ///< same (origin, seq) set, other digest: whole state pulled
  std::uint64_t versions_not_relayed = 0;  ///< versions of one (origin, seq) beyond max_versions: joined only
  std::uint64_t deltas_refused = 0;        ///< deltas the Admission refused (never applied; relayed)
  std::uint64_t states_refused = 0;        ///< state transfers the Admission refused (never joined)
  // Gossip membership (ReplicatorOptions::gossip).
  std::uint64_t probes = 0, probes_indirect = 0, suspicions = 0, refutations = 0, declared_gone = 0;
};

class Replicator {
 public:
  /// Installs itself as `g`'s delta sink. `g` and `t` must outlive the replicator.
  /// It also installs `g`'s origin namer (name_of()). Owner thread only.
  /// @pre No other Replicator serves `g` (the last one constructed would own its sink).
  Replicator(graph::Graph& g, Transport& t, ReplicatorOptions options = {});
  /// Removes the delta sink and origin namer from the graph; sends nothing (call leave() first
  /// for a clean goodbye). Owner thread only.
  ~Replicator();
  Replicator(const Replicator&) = delete;
  Replicator& operator=(const Replicator&) = delete;

  /// Announces this replica (a summary) and starts the heartbeat clock. Owner thread only.
  /// @pre restore() and set_admission(), if used, were called before.
  void start(std::int64_t now_ns);
  /// Before start(): the (origin, seq) set of a replica rebuilt from a store (its graph already
  /// holds those changes). Numbers of this replica in it are not published again: a replica that
  /// kept its incarnation goes on after the greatest. Owner thread only.
  /// @pre start() has not been called; the graph already holds every change in `applied`.
  void restore(const crdt::CausalContext& applied);
  /// Tells `journal` (owned by the caller, outliving this) every change joined from now on.
  /// Null stops it. Owner thread only.
  void set_journal(Journal* journal) { journal_ = journal; }
  /// Before start(): signs what this replica publishes and checks what it receives (owned by
  /// the caller, outliving this). Refused deltas are reported (kPermissionDenied), counted and
  /// never applied; their interval counts as received (every replica refuses them alike).
  /// Owner thread only.
  /// @pre start() has not been called (peers must never see this replica's deltas unsigned).
  void set_admission(Admission* admission) { admission_ = admission; }
  /// Handles one received sample, from any transport: checked first (validate.h); then a message
  /// that does not hold (e.g. a delta whose payload does not decode) is counted, reported and
  /// dropped; the replica is unchanged by it. Samples from this replica, or addressed to another,
  /// are ignored. Joins run the graph's subscribers; answers and relays go out through the
  /// transport before it returns. Owner thread only.
  /// @pre `now_ns` is on the clock tick() and start() use (an earlier time than one already seen
  ///      is taken as the latest seen).
  void on_sample(const Sample& s, std::int64_t now_ns);
  /// A sample its transport could not decode (its CDR does not follow the IDL type): counted and
  /// reported like any rejected sample. Owner thread only.
  void on_undecodable(const Error& e);
  /// A transport that detects departures itself (e.g. DDS liveliness) reports them here.
  /// `gone`: it left for good (its participant said so: a clean exit), so late packets of that
  /// incarnation are ignored; otherwise it may come back (a lease that ran out in a partition).
  /// An unknown peer is ignored. Owner thread only.
  void on_peer_lost(const PeerId& peer, bool gone = false);
  /// Timers: heartbeats, pull timeouts, gaps, liveness, buffer trimming; flushes coalesced deltas.
  /// Call it at least every heartbeat_ns (no heartbeat goes out before start()).
  /// Owner thread only.
  void tick(std::int64_t now_ns);
  /// Sends coalesced local deltas now (nothing when none is pending). Owner thread only.
  void flush();
  /// Applies and publishes a delta that originates elsewhere, under its own origin and sequence
  /// interval (its seq_lo/seq_hi): a world seed (graph::world_seed()). Idempotent: a delta this
  /// replica already holds is neither applied nor sent again.
  /// @returns true if it was new here; kInvalidArgument if it names no interval or is ours.
  ///          (kInvalidArgument also for a null origin or seq_hi < seq_lo.) Owner thread only.
  /// @pre `d` is a kDelta fragment as graph::world_seed() or graph::decode() builds it: it is
  ///      joined without further checks.
  Result<bool> seed(const graph::GraphDelta& d);
  /// Gateways (bridge.h): calls `cb` after each join of something received or seeded, with the
  /// delta as it came (applied, refused by the Admission, or an equivocation's second payload),
  /// or with null after a state transfer. Called inside the join: `cb` must not call back into
  /// this replicator (it queues the work). Replaces the previous callback. Owner thread only.
  void on_joined(std::function<void(const DeltaMsg*)> cb) { joined_cb_ = std::move(cb); }
  /// Gateways: joins a delta that another replica of this process received, unchanged (origin,
  /// interval, payload and signature), with every check a received delta gets (duplicate,
  /// equivocation, decoding, admission), and publishes it at once if it was new here.
  /// @returns true if it was new here; kInvalidArgument for a null or own origin, an empty
  ///          interval or no payload. Owner thread only.
  Result<bool> relay(const DeltaMsg& m);
  /// Gateways: joins `fragment`, what another replica of this process holds beyond this one,
  /// computed just now as other.graph().state_diff(graph().context()), with that replica's whole
  /// (origin, seq) set `applied` (never a state received from the network: its context would
  /// remove what this graph holds and the sender did not send). Then the peers learn the new set
  /// (gossip: the whole set offered; else the next summary). Owner thread only.
  /// @returns kPermissionDenied if the Admission refuses it (nothing joined).
  Status adopt_state(const graph::GraphDelta& fragment, const crdt::CausalContext& applied);
  /// Says goodbye so that peers drop this replica at once instead of after the lease.
  /// Flushes coalesced deltas first. Owner thread only.
  void leave();
  /// Sends a summary now (e.g. when the transport saw a newcomer appear). With gossip: a hello
  /// at the next tick, and only from a replica that started within 10 probe periods or hears
  /// nobody (members answer a newcomer's hello). Owner thread only.
  void announce();
  /// gossip: the transport discovered a peer (e.g. a DDS participant announcing its replica id
  /// and name): it is known alive from now on (probed, and asked for acknowledgements). A name
  /// that hashes to its id names it at once (Membership::kJoined); any other name is ignored and
  /// the peer is named when it first talks. An older incarnation of the same agent is gone.
  /// Ignored without gossip, for this replica, or a full peer table; a known peer is only named.
  /// Owner thread only.
  void introduce(const PeerCard& card);
  /// Offers this replica's whole (origin, seq) set to every peer, so that each pulls what it
  /// lacks and says when it holds all of it: what a clean stop does before it waits for
  /// peers_hold_all(). Repeated every pull_timeout_ns until leave(). With all-to-all summaries
  /// (gossip off) every heartbeat already does this, and it only sends one now. Owner thread only.
  void offer_all();
  /// Asks every live peer that has not acknowledged this replica's own changes up to `seq`
  /// (all_peers_hold()) to say so, now and every pull_first_timeout_ns until they all have: what
  /// a lock claim waits for. With gossip off the heartbeats already carry it. Owner thread only.
  void want_acks(std::uint64_t seq);
  /// Sends a summary as soon as the message being handled is fully applied (e.g. to acknowledge
  /// a lock claim promptly). Safe to call from change callbacks. Owner thread only.
  void announce_soon() { announce_soon_ = true; }

  /// True when this replica holds every change any live peer has told it about, and at least
  /// one peer is known. Peers suspected of false claims do not count; a state transfer in
  /// progress makes it false. Owner thread only.
  bool synced() const;
  /// @returns every remembered peer (live or recently gone), in id order. Owner thread only.
  std::vector<PeerInfo> peers() const;
  /// The name of the agent behind a replica id: this replica's own name, a peer's announced one
  /// (also after it left, if its name hashes to its id), or id.to_string() when unknown. The
  /// graph's change batches carry it (ChangeBatch::origin_name). Owner thread only.
  std::string name_of(const PeerId& id) const;
  /// name_of(), written into `out` (its capacity reused: the graph's origin namer). Owner thread only.
  void write_name(const PeerId& id, std::string& out) const;
  /// A replica as errors name it: "'speech' (00000000000000ab.3)" when its name is known, else
  /// its id. Owner thread only.
  std::string who(const PeerId& id) const;
  /// @returns the number of peers currently heard from. Owner thread only.
  std::size_t live_peer_count() const;
  /// Calls `cb` when a peer joins (once its first summary named it) or leaves (goodbye, lease,
  /// a newer incarnation, on_peer_lost()). Replaces the previous callback. Owner thread only.
  void on_membership(std::function<void(Membership, const PeerInfo&)> cb) { membership_cb_ = std::move(cb); }
  /// Called with a description of every rejected packet or message (malformed, oversized,
  /// equivocation, ...). The code tells the kind (kEquivocation for a forgery).
  /// Also kPermissionDenied (Admission refusals) and kRefused (a peer suspected). Replaces the
  /// previous callback. Owner thread only.
  void on_error(std::function<void(const Error&)> cb) { error_cb_ = std::move(cb); }
  /// True if `peer` is currently heard from. Owner thread only.
  bool peer_alive(const PeerId& peer) const;
  /// True if `peer` is heard from, or a live gateway peer says it is alive behind it (another
  /// robot's agent): whether a lock it holds lives. Owner thread only.
  bool member_alive(const PeerId& peer) const;

  // Gateways (bridge.h): what one side of a gateway learns from, and tells, the other side.
  /// Sets how far the replicas behind this side hold an origin: the bridge answers with the
  /// other side's peers_hold_upto(). A hold query a peer sends here is answered with the lesser
  /// of that and what this replica holds. Owner thread only.
  void set_behind(std::function<std::uint64_t(const PeerId& origin, std::uint64_t wanted)> vouch) {
    behind_ = std::move(vouch);
  }
  /// The greatest n such that every live agent peer (observers aside; the origin itself aside)
  /// said it holds `origin`'s 1..n (kHolds); asks those that did not say `wanted` yet (at most
  /// once a gap_grace_ns each). No peer: the greatest possible. Owner thread only.
  std::uint64_t peers_hold_upto(const PeerId& origin, std::uint64_t wanted);
  /// Calls `cb` when a peer says it holds more of an origin than it said before (kHolds).
  /// Replaces the previous callback. Owner thread only.
  void on_holds(std::function<void(const PeerId& origin)> cb) { holds_cb_ = std::move(cb); }
  /// Answers again the peers whose hold query about `origin` waits, now that the replicas behind
  /// may hold more. Owner thread only.
  void answer_holds(const PeerId& origin);
  /// Sets the replicas alive behind this side (sorted or not); the peers learn what changed at
  /// once and the whole list every probe_ns. Owner thread only.
  void set_members_behind(std::vector<Member> members);
  /// Gateways: the replicas alive behind this side, as last told to the peers (sorted by id).
  const std::vector<Member>& members_behind() const { return behind_out_; }
  /// The replicas the live gateway peers say are alive behind them (other robots' agents), each
  /// with its name, robot and gateway, in id order. Owner thread only.
  std::vector<Member> remote_members() const;
  /// The robot `id` runs on: the one its gateway said (remembered after it left), or, for this
  /// replica and its peers, robot_here(); "" when no gateway said. Owner thread only.
  std::string robot_of(const PeerId& id) const;
  /// The robot of this replica's domain: ReplicatorOptions::robot, else the one a gateway peer
  /// serves ("" outside a team). Owner thread only.
  std::string robot_here() const;
  /// Gateways: raised whenever replicas came behind this side (every beat carries it modulo 64).
  std::uint64_t behind_generation() const { return behind_generation_; }
  /// The latest generation gateway peer `peer` announced (modulo 64); -1 for another peer.
  int generation_heard(const PeerId& peer) const;
  /// @returns the live peers that are agents (not observers, not gateways) and the replicas the
  ///          live gateway peers say are alive behind them: what the other side of a gateway
  ///          tells its peers. Owner thread only.
  std::vector<Member> members_here() const;
  /// True if `peer` was heard from at some time and is still remembered (the peer table keeps
  /// peers that left until it needs their room). Owner thread only.
  bool peer_known(const PeerId& peer) const { return peers_.count(peer) > 0; }
  /// True if every live peer has told us (in its last summary) that it holds (origin, seq).
  /// True when no peer is live. Owner thread only.
  bool all_peers_hold(const PeerId& origin, std::uint64_t seq) const {
    return all_peers_hold(origin, seq, seq);
  }
  /// The same for every sequence number of origin in [lo, hi]. Owner thread only.
  /// @pre 1 <= lo <= hi.
  bool all_peers_hold(const PeerId& origin, std::uint64_t lo, std::uint64_t hi) const;
  /// True if every live agent peer (observers aside) whose summaries are believed has told us
  /// that it holds everything this replica holds: what a clean stop waits for (hand-over).
  /// True when there is no such peer. Owner thread only.
  bool peers_hold_all() const;
  /// Thread-safe: the last heartbeat this replica sent (its summary, without the state digest),
  /// or null before the first: what a keeper thread sends again while the owner thread is busy
  /// in user code (DdsReplica::keep_alive()), so that peers keep hearing a live agent.
  std::shared_ptr<const Sample> last_heartbeat() const;
  /// The last sequence number this replica published.
  /// @returns it (0 before the first); with `coalesce`, numbers still waiting for flush() count.
  ///          Owner thread only.
  std::uint64_t last_seq() const { return seq_; }
  /// The (origin, seq) pairs whose effects this replica holds.
  /// @returns a reference that lives as long as the replicator. Owner thread only.
  const crdt::CausalContext& applied() const { return applied_; }
  /// The bytes this replica's protocol state takes (peer table and what it records of each
  /// peer, names, rumors, the (origin, seq) set; not the graph and not the relay buffer, whose
  /// bound is buffer_bytes and which holds the equivocation records: the digest of each delta it
  /// keeps), estimated from the containers' sizes.
  /// Owner thread only.
  std::size_t protocol_bytes() const;
  /// True when no protocol work waits for a timer: no pull, gap, state transfer, set mismatch,
  /// acknowledgement request, offer, hello or coalesced delta pending. A host may then call
  /// tick() less often (heartbeats and probes keep their own periods). Owner thread only.
  bool idle() const {
    return !pulling_ && !gap_pending_ && !state_.active && mismatched_.empty() && want_acks_seq_ == 0 &&
           !offering_ && !hello_due_ && pending_lo_ == 0 && !announce_soon_;
  }
  /// @returns the protocol's counters. Owner thread only.
  const ReplicatorStats& stats() const { return stats_; }
  /// @returns the options it was built with (sample_ns as set_sample_ns() left it).
  ///          Owner thread only.
  const ReplicatorOptions& options() const { return opt_; }
  /// A sampling observer may change its period as it goes (e.g. to stay within a CPU budget).
  /// Ignored unless this is a sampling observer (options().sample_ns > 0) and ns > 0.
  /// Owner thread only.
  void set_sample_ns(std::int64_t ns) {
    if (opt_.sample_ns > 0 && ns > 0) opt_.sample_ns = ns;
  }
  /// @returns the graph this replicator serves. Owner thread only.
  graph::Graph& graph() { return g_; }

 private:
  using Buffered = BufferedDelta;
  using Version = BufferedDelta::Version;
  using Bytes = std::shared_ptr<const std::vector<std::uint8_t>>;
  using Peer = PeerRecord;
  /// The peer's detail, made when it has none (peer_table.h).
  PeerDetail& d(const Peer& p) { return peers_.detail(p, now_); }
  /// The peer's detail, or one with every field at its default.
  const PeerDetail& seen(const Peer& p) const { return peers_.seen(p); }
  /// What the membership callbacks and peers() tell of a peer.
  PeerInfo info_of(const Peer& p) const;
  // The state transfer answering our outstanding pull (one at a time).
  struct Reassembly {
    bool active = false;
    std::uint64_t count = 0;
    std::int64_t started_ns = 0;
    std::vector<Bytes> chunks;
    std::size_t received = 0, bytes = 0;
    crdt::CausalContext applied;
  };
  void on_local_delta(const graph::GraphDelta& d);
  void pull_if_stale();  // stale_pull_ns: pulls from a peer whose hash kept differing
  /// Signs, buffers and sends our delta [lo, hi], encoded into `bytes` (from fresh_bytes()).
  void publish(std::shared_ptr<std::vector<std::uint8_t>> bytes, std::uint64_t lo, std::uint64_t hi);
  /// An empty buffer for a delta we publish: one a dropped delta of ours left, when there is one.
  std::shared_ptr<std::vector<std::uint8_t>> fresh_bytes();
  void handle_own(const PeerId& from, const DeltaMsg& m);
  /// Decodes and checks a delta payload against its message; the error names what is wrong.
  Status decode_delta(const PeerId& from, const DeltaMsg& m);
  void apply_delta(const PeerId& from, const DeltaMsg& m, std::uint64_t digest);
  bool admitted(const PeerId& from, const DeltaMsg& m, std::uint64_t digest);
  Status admission_verdict(const PeerId& from, const DeltaMsg& m);
  /// The buffered delta under (origin, lo), or null: what tells a duplicate from an equivocation.
  Buffered* recorded(const PeerId& origin, std::uint64_t lo);
  void joined(const DeltaMsg* m) {
    if (joined_cb_) joined_cb_(m);
  }
  void equivocation(const std::string& what);
  /// A delta interval as errors name it: its origin by who(), then its numbers.
  std::string delta_of(const PeerId& origin, std::uint64_t lo, std::uint64_t hi) const;
  void equivocate(const PeerId& from, const DeltaMsg& m, std::uint64_t digest, const std::string& what);
  void skip_own_numbers_to(std::uint64_t hi);
  bool counts(const Peer& p) const;
  // A gateway's generation or list version `ahead` of the one taken at `taken_ns`: taken if newer
  // (ahead in the window), or, whatever it is, once a reordered beat can no longer explain it.
  bool newer_from_gateway(bool ahead, std::int64_t taken_ns) const;
  void handle(const PeerId& from, const SummaryMsg& m);
  void handle(const PeerId& from, const DeltaMsg& m);
  void handle(const PeerId& from, const PullMsg& m);
  void answer_with_state(const PeerId& from, const PullMsg& m);
  /// False while a state went to `from` less than a first-pull patience ago.
  bool state_answer_allowed(const PeerId& from);
  void handle(const PeerId& from, const StateMsg& m);
  void handle(const PeerId& from, const ByeMsg& m);
  Peer* heard_from(const PeerId& from);
  void mark_left(Peer& p);
  void send_summary(bool with_digest = false);
  void pull_from(const PeerId& target, bool whole_state = false);
  /// 64 bits of the graph's digest (never 0), computed again only after the graph changed.
  std::uint64_t state_digest();
  void check_digest(const PeerId& from, Peer& p, std::uint64_t digest);
  bool behind(const Peer& p) const;
  // Gossip (replicator_gossip.cc).
  /// A beat to `to` (null: everyone); with `rumors`, the membership news due piggybacked.
  SummaryMsg beat(Beat b, const PeerId& to, bool rumors = true);
  void send_beat(Beat b, const PeerId& to, const PeerId& subject = {});
  /// A kFull beat: this replica's whole (origin, seq) set, to `to` (null: everyone).
  void send_full(const PeerId& to);
  void say_hello();
  /// ReplicatorOptions::hello_answers, or 3 once a transport introduced a peer (0: everyone).
  int hello_answers() const { return opt_.hello_answers > 0 ? opt_.hello_answers : introduced_ ? 3 : 0; }
  /// A peer known to exist (introduced, or rumored alive): alive from now on; an older incarnation
  /// of its agent is gone. Null when the table is full.
  Peer* add_peer(const PeerId& peer);
  void retire_older_incarnations(const PeerId& peer);
  /// Remembers `name` for `from`'s agent (bounded) if it hashes to the agent's id.
  /// @returns whether it does.
  bool remember_name(const PeerId& from, const std::string& name);
  void repair_own(const PeerId& to, Peer& p, std::uint64_t your_seq);
  void handle_gossip(const PeerId& from, Peer& p, const SummaryMsg& m);
  void hear_rumor(const Rumor& r);
  void spread(const Rumor& r);
  void suspect(Peer& p);
  void declare_dead(Peer& p);
  void gossip_tick();
  void probe_tick();
  void trim_buffer_gossip();
  /// Gossip: keeps the peers' details within kMaxDetails, but those a rule waits on.
  void trim_details();
  static constexpr std::size_t kMaxDetails = 16;
  /// Gossip: names remembered at most (a peer's detail keeps its own).
  static constexpr std::size_t kMaxNames = 32;
  const PeerId* next_probe_target();
  const PeerId* next_digest_target();
  void refresh_set_hash() const;
  std::uint64_t set_hash() const { refresh_set_hash(); return set_hash_; }
  std::uint64_t set_count() const { refresh_set_hash(); return set_count_; }
  std::int64_t suspect_timeout() const;
  /// Buffers a delta and its digest (nothing when its (origin, lo) is buffered already); `ours`:
  /// its bytes came from fresh_bytes() and go back to the spares when it is dropped.
  void remember(const PeerId& origin, std::uint64_t lo, std::uint64_t hi, std::uint64_t digest, Bytes bytes,
                Bytes signature, bool ours = false);
  void evict_front();
  std::list<Buffered>::iterator erase_buffered(std::list<Buffered>::iterator it);
  /// Stores `applied` as p's set; false (rejected, p unchanged) beyond max_peer_ranges.
  bool take_peer_set(const PeerId& from, Peer& p, crdt::CausalContext applied);
  void trim_buffer();
  // Teams (replicator_behind.cc).
  struct Asker {  // a peer waiting for us to hold, with what is behind us, origin's 1..wanted
    PeerId origin, asker;
    std::uint64_t wanted = 0, told = 0;
    std::int64_t since_ns = 0;
  };
  struct Behind {  // a replica alive behind a gateway peer
    PeerId via;
    std::int64_t heard_ns = 0;
    std::string name, robot;  // as the gateway said ("" not said)
  };
  static constexpr std::size_t kMaxHolds = 16, kMaxAskers = 256, kMaxGateways = 64;
  static constexpr std::uint8_t kStaleReports = 4;  ///< stale_pull_ns: differing reports in a row
  PeerDetail::Held& held_entry(Peer& p, const PeerId& origin);
  std::uint64_t held(const Peer& p, const PeerId& origin) const;
  std::uint64_t vouch(const PeerId& origin, std::uint64_t wanted);
  void send_hold(Beat b, const PeerId& to, const PeerId& origin, std::uint64_t n);
  void handle_team_beat(const PeerId& from, Peer& p, const SummaryMsg& m);
  void check_askers(const PeerId* origin);
  /// Asks again for acknowledgements of our latest claim (want_acks()) when a gateway peer's
  /// earlier ones may no longer cover everyone behind it.
  void ask_again();
  /// Teams: answers waiting askers, says who is behind us every probe period, and (on a sweep)
  /// forgets replicas behind gateway peers not heard of again.
  void behind_tick(bool sweep);
  /// Gateways: the whole list of the replicas behind us, to `to` (null: everyone).
  void tell_behind(const PeerId& to);
  void queue(const PeerId& to, Message msg);
  void send_queued();
  void reject(const Error& e);

  graph::Graph& g_;
  Transport& t_;
  ReplicatorOptions opt_;
  PeerId self_;
  std::int64_t now_ = 0;
  std::int64_t next_heartbeat_ = 0;
  std::int64_t next_sample_ = 0;
  std::int64_t next_stale_pull_ns_ = 0;  // the earliest time of the next pull on stale hashes alone
  std::int64_t next_digest_ = 0;
  bool started_ = false;
  std::uint64_t state_version_ = 0;  // bumped by every local commit and every join
  std::uint64_t digest_version_ = ~0ull, digest_ = 0;

  std::uint64_t seq_ = 0;  // last local sequence number
  Journal* journal_ = nullptr;
  Admission* admission_ = nullptr;
  crdt::CausalContext applied_;
  graph::GraphDelta pending_;  // coalesced local deltas
  std::uint64_t pending_lo_ = 0;

  std::list<Buffered> buffer_;
  using BufferIndex = std::map<std::uint64_t, std::list<Buffered>::iterator>;  // lo -> entry
  std::map<PeerId, BufferIndex> buffer_index_;  // an origin's index may be empty (see trim_buffer())
  std::size_t buffer_bytes_ = 0;
  BufferSpares<BufferIndex> spare_;
  /// Forgets origins whose index is empty, once there are many of them.
  void forget_empty_origins();

  PeerTable peers_;
  std::map<std::uint64_t, std::string> names_;  // agent id -> announced name (bounded)
  std::map<std::uint64_t, std::string> robots_;  // agent id -> robot, as gateways said (bounded)
  std::map<PeerId, std::string> gateway_robots_;  // gateway peer -> the robot it serves (bounded)
  std::size_t peer_ranges_ = 0;  // ranges of all peers' applied sets
  Reassembly state_;
  std::size_t pending_bytes_ = 0;  // estimated size of the coalesced interval

  // Outstanding pull.
  bool pulling_ = false;
  PeerId pull_target_;
  std::uint64_t pull_request_ = 0;
  std::int64_t pull_sent_ns_ = 0;     // last sign of progress (sent, or a chunk arrived)
  int pull_timeouts_in_a_row_ = 0;
  PeerId last_failed_target_;
  bool gap_pending_ = false;
  std::int64_t gap_since_ns_ = 0;
  PeerId gap_peer_;

  // Gossip state.
  std::uint64_t life_ = 0;
  std::int64_t started_ns_ = 0;
  std::int64_t next_probe_ns_ = 0;
  std::int64_t next_forget_ns_ = 0;
  PeerId probe_target_, probe_cursor_;
  std::int64_t probe_sent_ns_ = -1;
  bool probe_indirect_ = false;
  std::uint64_t probes_ = 0;
  struct Spreading {
    Rumor rumor;
    int left;
  };
  std::vector<Spreading> rumors_;
  std::vector<PeerId> ack_to_;
  std::uint64_t want_acks_seq_ = 0;
  std::int64_t next_ack_request_ns_ = 0;
  std::int64_t next_rediscover_ns_ = 0;
  bool hello_due_ = false;
  std::int64_t next_hello_ns_ = 0;
  int hellos_ = 0;  // hellos sent for new matches: each waits twice as long as the one before
  bool offering_ = false;
  bool addressed_ = false;  // the sample being handled was addressed to this replica
  std::array<std::uint8_t, 16> sender_{};  // the sample being handled: Sample::sender
  bool introduced_ = false;  // the transport introduced a peer (hello_answers())
  std::int64_t next_offer_ns_ = 0;
  bool digest_due_ = false;
  PeerId digest_to_;  // the peer the digest goes to this period (next_digest_target())
  Rng rng_{0};  // seeded from the replica id at start(): deterministic, and apart for each replica
  std::int64_t applied_changed_ns_ = 0;
  mutable std::uint64_t hash_version_ = ~0ull, set_hash_ = 0, set_count_ = 0;
  std::map<PeerId, std::int64_t> mismatched_;  // peers whose last report showed what we lack
  // Teams (replicator_behind.cc).
  std::function<std::uint64_t(const PeerId&, std::uint64_t)> behind_;
  std::function<void(const PeerId&)> holds_cb_;
  std::vector<Asker> askers_;
  std::uint64_t askers_version_ = 0;  // state_version_ when the askers were last checked
  std::uint64_t claims_seq_ = 0;      // the greatest number want_acks() was given
  std::map<PeerId, Behind> remote_;   // replicas alive behind gateway peers
  std::vector<Member> behind_out_;    // gateway: the replicas alive behind us, as told (sorted)
  std::uint64_t behind_generation_ = 0;  // gateway: raised whenever replicas came behind us
  std::uint64_t behind_version_ = 0;     // gateway: raised whenever that list changed
  std::int64_t next_behind_ns_ = 0;

  std::vector<Sample> outbox_;
  mutable std::mutex heartbeat_mu_;
  std::shared_ptr<const Sample> heartbeat_;  // guarded by heartbeat_mu_
  bool announce_soon_ = false;
  graph::GraphDelta scratch_;
  ReplicatorStats stats_;
  std::function<void(Membership, const PeerInfo&)> membership_cb_;
  std::function<void(const Error&)> error_cb_;
  std::function<void(const DeltaMsg*)> joined_cb_;
};

}  // namespace quiver::agents
