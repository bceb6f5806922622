#pragma once
/// @file
/// The replication protocol over Eclipse Cyclone DDS 0.10 (C API, wrapped once here).
///
/// Messages are IDL types (agents/transport/wire/idl/quiver_wire.idl) serialized as CDR by Cyclone; each
/// message kind has its own topic and QoS: summaries are keyed by sender with KEEP_LAST(1)
/// (their instance goes NOT_ALIVE when the sender's participant loses liveliness: that is how a
/// crashed agent is noticed within about one lease), deltas, pulls and state chunks are RELIABLE
/// KEEP_ALL with a bounded blocking time: a write that times out because a reader lags is
/// counted and dropped, and the protocol recovers it (the reader pulls it later).
///
/// Nothing runs on DDS threads: the owner thread blocks in wait() on a waitset and takes
/// samples itself in drain().
///
/// Threading: the owner thread is the one that calls wait() and drain() (and the other members
/// unless marked otherwise); send() and wake() may be called from any thread. Errors are values:
/// create() returns them, send() counts them (stats()); nothing here throws.
///
/// NETWORK SAFETY: by default the transport builds its own Cyclone domain from an embedded
/// configuration bound to 127.0.0.1 with multicast off, and `CYCLONEDDS_URI` is NOT consulted.
/// Another configuration is an explicit opt-in (DdsConfig::Source::kEnvironment or kXml).
///
/// DDS SECURITY (docs/security.md): with DdsConfig::security set, the participant loads Cyclone's
/// standard plugins (authentication, access control, cryptography) with the agent's credentials:
/// it meets only participants whose certificates the same CA signed (and did not revoke), and the
/// governance document encrypts and signs everything they exchange.

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "quiver/agents/replica/replication/messages.h"
#include "quiver/agents/replica/replication/transport.h"
#include "quiver/agents/replica/replication/validate.h"
#include "quiver/agents/replica/security/keys.h"
#include "quiver/base/result.h"

namespace quiver::agents::inline transport {

/// The participant lease from which the embedded configurations pace Cyclone for many processes.
inline constexpr std::int64_t kManyProcessesLeaseNs = 5'000'000'000;

struct DdsConfig {
  enum class Source : std::uint8_t {
    kLoopback,     ///< embedded: 127.0.0.1 only, multicast off (the default)
    kEnvironment,  ///< opt-in: whatever CYCLONEDDS_URI says (multi-host deployments)
    kXml,          ///< opt-in: the `xml` given here
  };
  Source source = Source::kLoopback;
  std::string xml;
  std::uint32_t domain = 0;                    ///< the DDS domain id agents meet in
  /// The agent's name and role, announced with its replica id in the participant's user data:
  /// what take_new_peers() gives the others.
  std::string name;
  bool observer = false;
  bool gateway = false;                        ///< one side of a robot team's gateway (docs/teams.md)
  /// Participant lease (crash detection time). From kManyProcessesLeaseNs on, the embedded
  /// configurations also pace Cyclone for many processes on one host (slower heartbeats; on
  /// loopback one port and 64 KiB datagrams; docs/protocol.md).
  std::int64_t lease_ns = 1'000'000'000;
  int xmit_loss_permille = 0;                  ///< testing: Cyclone drops this share of sent packets
  bool own_domain_instance = false;            ///< a private Cyclone instance (threads, sockets) for this transport
  std::int64_t max_blocking_ns = 100'000'000;  ///< how long a reliable write may wait for a lagging reader
  /// Read deltas, pulls and states best effort: writers never wait for this participant (a viewer
  /// or a recorder that falls behind must not hold the agents back). What it misses it pulls, as
  /// after any loss.
  bool best_effort_reader = false;
  /// Subscribe to deltas. Off for a sampling observer (ReplicatorOptions::sample_ns): no writer
  /// then sends it a single delta; it pulls context diffs instead.
  bool read_deltas = true;
  /// DDS Security credentials (security::agent_files()); none: an unsecured participant, which
  /// secured ones neither hear nor answer. Cyclone loads the security plugins once per domain
  /// instance and then refuses participants without credentials in it, so a secured and an
  /// unsecured transport of one process need `own_domain_instance`; two identities under one CA
  /// may share an instance. A secured private instance takes a process-local domain id in
  /// 0..230 (Cyclone checks the local id against the governance), at most 231 per process.
  std::optional<security::DdsSecurityFiles> security;
};

/// The folder Cyclone's security plugins (libdds_security_{auth,ac,crypto}.so) are loaded from:
/// $QUIVER_DDS_SECURITY_LIB_DIR if set, else the one found at build time ("" if none).
/// Thread-safe (reads the environment).
/// @returns that folder, unchecked (set_security_qos() checks the files).
std::string dds_security_plugin_dir();

/// Sets on a participant QoS (a `dds_qos_t*`) the properties that make Cyclone load its security
/// plugins with `f`: for code that creates DDS participants itself (the rogue suite's attacker).
/// Thread-safe on distinct `qos`.
/// @pre `qos` is a live dds_qos_t (dds_create_qos()).
/// @returns kNotFound if the plugins' folder is unknown or a plugin library is missing;
///          kInvalidArgument if a credential file of `f` is not named (the CRL is optional).
///          `qos` may hold some of the properties after an error.
Status set_security_qos(struct dds_qos* qos, const security::DdsSecurityFiles& f);

/// The largest sample the embedded configuration lets Cyclone accept or send: a delta at the
/// protocol's limit (SampleLimits::max_payload_bytes) with room for its header.
inline constexpr std::size_t kMaxSampleBytes = SampleLimits{}.max_payload_bytes + (64u << 10);

/// The embedded loopback configuration for `cfg` (lease, loss, external domain id filled in).
/// Pure and thread-safe.
/// @returns the Cyclone XML text.
std::string loopback_config_xml(const DdsConfig& cfg);

/// A domain on a real network (a robot team's, docs/teams.md): explicit opt-in, unicast only.
struct NetworkDomain {
  std::string address;             ///< this host's address on that network: the only interface used
  std::vector<std::string> peers;  ///< the addresses discovery is sent to (every host of the network)
  std::string tag;                 ///< Cyclone's discovery tag: participants with another never match
  int max_participant_index = 4;   ///< participants per host (and one more)
};

/// The embedded configuration for a domain on a network: `net`'s interface and peers, multicast
/// off, never routed; lease, loss and external domain id from `cfg` as loopback_config_xml().
/// Pure and thread-safe. @pre `net`'s addresses and tag are checked (no XML in them).
/// @returns the Cyclone XML text.
std::string network_config_xml(const NetworkDomain& net, const DdsConfig& cfg);

/// Sends Cyclone DDS's own log lines (warnings about malformed packets, samples that fail to
/// deserialize, ...) to `sink` instead of stderr, process-wide; null restores stderr. `sink` runs
/// on Cyclone's threads: it must be thread-safe and quick. This call is thread-safe.
void route_dds_log(std::function<void(const std::string&)> sink);

class DdsTransport final : public Transport {
 public:
  struct Stats {
    std::uint64_t samples_written = 0;
    std::uint64_t write_timeouts = 0;
    std::uint64_t write_errors = 0;
    std::uint64_t samples_taken = 0;
    std::uint64_t peers_lost = 0;
  };

  /// Creates the domain (unless shared), participant, topics, writers, readers and waitset.
  /// Any thread; the thread that then calls wait() and drain() owns the transport.
  /// @pre `self` is the id of the replica this transport serves (announced in the participant).
  /// @returns the transport, or kInvalidArgument (the domain is already open in this process
  ///          with another configuration or security setting; a credential file not named),
  ///          kNotFound (the security plugins are missing), kRefused (Cyclone refused the secured
  ///          participant; the message quotes its log), kTimeout / kTransport (another DDS
  ///          failure).
  static Result<std::unique_ptr<DdsTransport>> create(const PeerId& self, const DdsConfig& cfg);
  /// Deletes the DDS entities (a shared domain when its last user goes). Owner thread only.
  /// @pre No other thread is in send() or wake() (stop keeper threads first).
  ~DdsTransport() override;
  DdsTransport(const DdsTransport&) = delete;
  DdsTransport& operator=(const DdsTransport&) = delete;

  /// Thread-safe: writes `s` as one sample of its topic. A write that times out (a reader lags
  /// beyond max_blocking_ns) is counted and dropped: the protocol recovers it.
  /// Other write failures are counted too (stats().write_errors); nothing is reported. May block
  /// up to DdsConfig::max_blocking_ns.
  /// @pre as Transport::send(); a DeltaMsg's payload and a StateMsg's chunk are not null.
  void send(const Sample& s) override;

  /// Blocks until samples arrive, wake() is called, or `timeout_ns` passes.
  /// A negative `timeout_ns` polls (returns at once). Owner thread only.
  void wait(std::int64_t timeout_ns);
  /// Takes every available sample: `on_sample` per message (addressed to us or to all),
  /// `on_lost(peer, gone)` per peer whose summary instance lost liveliness (gone = false: it may
  /// come back) or was disposed (gone = true: a clean exit).
  /// The callbacks run synchronously on the calling thread; samples are decoded but not
  /// validated (Replicator::on_sample() does that). Owner thread only.
  void drain(const std::function<void(const Sample&)>& on_sample,
             const std::function<void(const PeerId&, bool)>& on_lost);
  /// Thread-safe: makes a concurrent wait() return.
  /// If no wait() is in progress, the next one returns at once.
  void wake();
  /// True (once) when a new remote summary reader matched since the last call: a newcomer
  /// appeared, so it is worth announcing ourselves now rather than at the next heartbeat.
  /// Owner thread only.
  bool take_new_match();
  /// The peers DDS discovered since the last call: each participant announces its replica id,
  /// role (observer, secured) and name in its user data (DdsConfig::name). This replica's own,
  /// malformed ones, and those secured when this one is not (or the reverse: they exchange no
  /// sample) are left out; a name is passed on as announced (Replicator::introduce() checks it). What
  /// Replicator::introduce() takes, so that gossip replicas know every peer without hellos.
  /// Owner thread only.
  std::vector<PeerCard> take_new_peers();
  /// Testing: the whole domain instance stops receiving (deaf) and/or sending (mute); both are
  /// reset after `reset_after_ns` (a negative value: never). Owner thread only.
  /// @returns kTimeout / kTransport if Cyclone refuses.
  Status set_deafmute(bool deaf, bool mute, std::int64_t reset_after_ns);
  /// Disposes our summary instance so peers see us leave at once. Owner thread only.
  void dispose_self();

  /// @returns the transport's counters. Owner thread only; send() updates them from any thread
  ///          (plain integers): read them when no other thread is sending.
  const Stats& stats() const { return stats_; }
  /// @returns the replica id given to create(). Any thread.
  const PeerId& self() const { return self_; }

 private:
  DdsTransport() = default;
  struct Impl;
  std::unique_ptr<Impl> impl_;
  PeerId self_;
  Stats stats_;
};

}  // namespace quiver::agents
