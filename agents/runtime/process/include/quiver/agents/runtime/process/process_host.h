#pragma once
/// @file
/// The process host: one agent as its own OS process over Cyclone DDS (the embedded loopback
/// configuration unless told otherwise). It creates the replica, seeds a world file if given,
/// waits briefly to join its peers, starts the agent, and runs it until SIGINT/SIGTERM (or
/// --run-for), logging through spdlog with the agent's name; bad input and peers coming and going
/// are logged rate-limited by kind. A user's main() is a few lines:
///
/// ```cpp
/// int main(int argc, char** argv) {
///   MyAgent agent;
///   return quiver::agents::run_process(agent, argc, argv);
/// }
/// ```

#include <cstdint>
#include <string>

#include "quiver/agents/runtime/process/dds_replica.h"
#include "quiver/agents/runtime/api/agent.h"
#include "quiver/base/result.h"

// CLI11's App only by name: a user of run_process(agent, argc, argv) does not parse CLI11's
// headers (seconds per file); one who adds its flags to an App includes <CLI/CLI.hpp> itself.
namespace CLI {
class App;
}

namespace quiver::agents::inline runtime {

/// The standard flags of an agent process (and of every command that joins a DDS domain).
struct ProcessFlags {
  std::uint32_t domain = 0;
  std::string dds_config = "loopback";
  int loss_permille = 0;
  /// The DDS participant lease (DdsConfig::lease_ns): a crashed or cut-off agent is noticed within
  /// it, and every process receives a few discovery packets per peer per lease (docs/protocol.md,
  /// "Over DDS": a longer lease for many processes on one host).
  double lease_s = 1;
  std::string world;
  std::string world_text;  ///< a world given as text (when `world` names no file), e.g. embedded
  std::uint64_t seed = 1;
  int status_ms = 0;
  bool final_status = true;  ///< print one status line after a clean stop (--no-final-status: none)
  double run_for_s = 0;
  double join_wait_s = 1.5;
  double hand_over_s = 2;  ///< on a clean stop, replicate up to this long until the peers hold all it published
  double hang_s = 1;       ///< a callback running longer is reported as hung (0: never)
  std::string store;                ///< durable store directory (empty: none)
  std::string durability = "batch";  ///< none | batch | always
  double store_compact_mb = 64;      ///< compact when the log holds this much (and more than the snapshot)
  /// DDS Security credentials directory (`quiver keys`, docs/security.md); empty: unsecured.
  /// run_process() and DdsFlags authenticate as the agent's name (enable_security()).
  std::string security;
  /// The shared vocabulary every agent of the domain loads (docs/schema.md); empty: none.
  std::string schema;
  /// "gossip" (the default; ReplicatorOptions::gossip: constant-size beats to one peer per
  /// period; docs/protocol.md) or "all-to-all" (every heartbeat, the whole (origin, seq) set to
  /// every peer).
  std::string membership = "gossip";

  /// --domain, --dds-config, --loss-permille, --lease, --membership (the DDS ones) on `cmd`.
  /// And --security, --schema. The options write into this object. @pre `cmd` is not null; this object
  ///      outlives the parse.
  void add_dds(CLI::App* cmd);
  /// The DDS ones and --world, --seed, --status-ms, --no-final-status, --run-for, --join-wait,
  /// --hang, --hand-over, --store, --durability.
  /// And --store-compact-mb. @pre as add_dds().
  void add_all(CLI::App* cmd);
  /// Ok, or what is wrong with a value the command line would have refused (set in code, e.g. from
  /// Python's run_agent()): a membership, durability, lease, hand-over or compaction size.
  /// replica_options() and every command's create_agent() check first.
  Status check() const;
  /// The replicator options these flags choose (--membership) on `o`. @pre check() is ok.
  void apply_to(ReplicatorOptions& o) const { o.gossip = membership == "gossip"; }
  /// Sets the DDS configuration these flags choose (domain, source, loss) on `c`.
  /// For a `dds_config` that names a file, reads it as the XML. Security is not set here
  /// (enable_security()).
  /// @returns kIo if that file cannot be read (`c` may be partly set then).
  Status apply_to(DdsConfig& c) const;
  /// Loads --schema (if given) into `o.schema`.
  /// @returns the schema file's error, naming --schema.
  Status apply_schema(DdsReplicaOptions& o) const;
};

/// The replica options the flags choose for an agent named `name`: DDS configuration, membership,
/// security credentials, store, seed. @returns them, or the error of the flag that is wrong
/// (an unreadable --dds-config file, --security, --durability), naming it.
Result<DdsReplicaOptions> replica_options(const std::string& name, const ProcessFlags& flags);

/// Runs `agent` as this process's agent until SIGINT/SIGTERM or `flags.run_for_s`. Prints a JSON
/// status line on stdout every `flags.status_ms` (and one at the end). @returns the exit status:
/// 0, or 2 when it could not start (the reason on stderr).
/// The calling thread is the replica's owner and runs the agent. It installs SIGINT/SIGTERM
/// handlers and routes Cyclone's log for its duration, process-wide.
/// @pre No other run_process() runs in this process; `agent` is attached to no host.
/// `why_not_started`, if given, receives the error when it returns 2.
int run_process(Agent& agent, const ProcessFlags& flags, Error* why_not_started = nullptr);
/// Parses the standard flags from the command line (--help lists them), then runs.
/// @returns as the other overload; for --help or a flag error, CLI11's exit code (0 for --help)
///          after printing the help or the error. @pre as the other overload.
int run_process(Agent& agent, int argc, char** argv);

/// Makes the running run_process() return as if SIGTERM had arrived (running actions cancelled,
/// teardown() called). Thread-safe and async-signal-safe; e.g. for an agent whose code failed. A
/// call before run_process() starts is forgotten (each run starts unstopped).
void request_stop();

/// For a process's own main loop (e.g. a gateway's): forgets an earlier stop request and makes
/// SIGINT and SIGTERM request one. Process-wide; call it from the main thread.
void stop_on_signals();
/// @returns whether a stop was requested (a signal, or request_stop()). Thread-safe.
bool stop_requested();

/// Resident memory of this process in KiB (Linux; 0 elsewhere).
/// @returns that size, or 0 if /proc/self/statm cannot be read. Thread-safe.
long resident_kb();

}  // namespace quiver::agents
