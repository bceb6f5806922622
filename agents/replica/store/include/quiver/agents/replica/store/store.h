#pragma once
/// @file
/// A replica's durable store (docs/persistence.md): an LMDB environment in one directory holding
/// a snapshot of the replica's state plus a log of every change joined since, compacted in the
/// background. An agent that opens its store on start gets its replica back after a crash or a
/// power cut, rejoins, and pulls only what it missed.
///
///  - Every record (log entry, snapshot) carries a checksum; a store whose records do not verify,
///    or whose file is shorter than LMDB's meta pages say, is refused with an error naming the
///    directory and the record, and the caller starts afresh from its peers.
///  - Durability (when the log reaches the disk relative to publishing):
///      none    written by a background thread, never flushed by us (survives a crash of the
///              process, not of the machine);
///      batch   written and flushed (fdatasync) by a background thread every `batch_ns`;
///              publishing does not wait;
///      always  written and flushed before the commit returns and before its delta is published.
///  - Incarnations: a store proves that no dot its replica published was lost only if every run
///    that wrote it flushed before publishing (`always`) and it opened intact; then the replica
///    keeps its incarnation (its peers see the same replica come back). Otherwise it takes a new
///    one, recorded durably before anything is published under it.
///
/// Threading: one owner thread (the replicator's) calls everything; the store's own thread
/// writes (none, batch) and compacts. One process at a time may open a directory.

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>

#include "quiver/agents/replica/replication/journal.h"
#include "quiver/crdt/causal_context.h"
#include "quiver/graph/graph.h"
#include "quiver/base/result.h"

namespace quiver::agents::inline replica {

enum class Durability { kNone, kBatch, kAlways };

std::string_view to_string(Durability d);
/// "none", "batch" or "always".
Result<Durability> parse_durability(std::string_view s);

/// A write the store is about to make (fault injection: StoreFaults).
struct StoreWrite {
  enum class What : std::uint8_t { kMeta, kLog, kSnapshot } what = What::kLog;
  std::size_t bytes = 0;                             ///< bytes of records, snapshot or meta
  std::uint64_t first_record = 0, last_record = 0;   ///< kLog: the records it holds
};

/// A fault injected into one write (the simulator's disks; tests).
struct StoreFault {
  enum class Kind : std::uint8_t {
    kNone,
    kNoSpace,  ///< the write fails as on a full disk (ENOSPC); nothing of it reaches the disk
    /// kLog only: the power fails mid-write. The records before the last reach the disk, of the
    /// last only its first `keep` bytes (or, with `flip`, all of it with byte `keep` inverted),
    /// and the write fails.
    kTear,
    /// The disk says the write succeeded and keeps nothing of it (a lying disk: the control of
    /// tests that must catch lost acknowledged writes).
    kLie,
  } kind = Kind::kNone;
  std::size_t keep = 0;
  bool flip = false;
};

struct StoreFaults {
  /// Consulted before every write transaction, on the thread that writes it. Empty: no faults.
  std::function<StoreFault(const StoreWrite&)> before_write;
  /// Under `always`, called when a write fails, instead of printing the error and aborting the
  /// process (fail-stop). Whoever sets it must make sure nothing the store's caller does next
  /// leaves the process (the simulator marks the host down at once, then kills it).
  std::function<void(const Error&)> fail_stop;
};

struct StoreOptions {
  std::string dir;                            ///< created if absent
  Durability durability = Durability::kBatch;
  /// batch: the longest a change waits for its flush; none: for its write. 0: only when sync()
  /// asks (the simulator flushes in virtual time).
  std::int64_t batch_ns = 20'000'000;
  /// Compact when the log holds this many bytes and more than the snapshot (0: never).
  std::size_t compact_log_bytes = 64u << 20;
  std::size_t map_bytes = std::size_t{64} << 30;  ///< LMDB map size (address space, not disk)
  StoreFaults faults;                         ///< none unless set (simulation, tests)
};

struct StoreStats {
  std::uint64_t records_appended = 0;
  std::uint64_t bytes_appended = 0;
  std::uint64_t flushes = 0;        ///< write transactions committed for the log
  std::uint64_t syncs = 0;          ///< fdatasync calls
  std::uint64_t compactions = 0;
  std::uint64_t records_loaded = 0;  ///< log records replayed at open
};

/// What open() found.
struct StoreOpening {
  bool created = false;          ///< the directory held no store
  bool incarnation_kept = false;  ///< the replica keeps the incarnation it had
  std::uint64_t incarnation = 0;  ///< the incarnation to run under
  std::uint64_t records = 0;      ///< log records replayed
  std::size_t snapshot_bytes = 0;
  /// Not empty when the last log record did not verify and was dropped: the trace of a write
  /// the power cut (a torn write), named ("store DIR: log record 12: checksum mismatch ...").
  /// Under `always` that write was never acknowledged (a commit returns after its flush). The
  /// replica then takes a new incarnation. Damage anywhere else is refused (load()).
  std::string torn_tail;
};

class Store final : public Journal {
 public:
  /// Opens (or creates) the store of agent `name` in `opt.dir`. `fresh_incarnation` is the
  /// incarnation to take if the store cannot keep its own. Fails with a message naming the
  /// directory and what is wrong: kMalformed / kTruncated (a damaged store), kUnsupportedVersion,
  /// kInvalidArgument (another agent's store), kAlreadyExists (open in another process), kIo.
  static Result<std::unique_ptr<Store>> open(const StoreOptions& opt, std::string_view name,
                                             std::uint64_t fresh_incarnation);
  ~Store() override;
  Store(const Store&) = delete;
  Store& operator=(const Store&) = delete;

  const StoreOpening& opening() const { return opening_; }
  /// Joins the stored replica into `g` (a new, empty graph whose id has opening().incarnation)
  /// and returns the (origin, seq) set it holds (for Replicator::restore). Checks every record;
  /// kMalformed names the first one that fails (the graph then holds part of the store: discard
  /// it, set the store aside and start afresh).
  Result<crdt::CausalContext> load(graph::Graph& g);

  // Journal (owner thread).
  void local(std::uint64_t seq, std::span<const std::uint8_t> delta) override;
  void remote(const graph::ReplicaId& origin, std::uint64_t lo, std::uint64_t hi,
              std::span<const std::uint8_t> delta) override;
  void state(std::span<const std::uint8_t> fragment, const crdt::CausalContext& applied) override;
  void skipped(std::uint64_t lo, std::uint64_t hi) override;

  /// Writes and flushes everything appended so far (whatever the policy); then waits for a
  /// compaction in progress. For a clean stop and for tests.
  Status sync();
  /// Compacts now (on the store's thread) and waits for it.
  Status compact();
  /// The first error the store met (a full disk, say), or OK. After one, under `none` and
  /// `batch`, appends are dropped (the next start takes a new incarnation: `always` was not
  /// kept). Under `always` every append is still written, and one whose write fails stops the
  /// process (fail-stop: the commit it belongs to has not returned and its delta was not
  /// published, so nothing acknowledged is lost); a failed compaction only stops compacting.
  Status health() const;
  StoreStats stats() const;
  const StoreOptions& options() const;

  /// Moves a store that cannot be opened aside (to DIR.corrupt-N), keeping it for inspection.
  /// Returns the new path.
  static Result<std::string> set_aside(const std::string& dir);

 private:
  Store();
  struct Impl;
  std::unique_ptr<Impl> impl_;
  StoreOpening opening_;
};

}  // namespace quiver::agents
