#pragma once
/// @file
/// A replica on DDS: one graph replica, its replicator, and the Cyclone DDS transport, driven by one
/// owner thread. The owner thread is whichever thread calls spin_*(); every graph read and
/// write, every change event and every protocol step happens there. Other threads talk to the
/// agent only through post() and stop(), which are thread-safe.

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "quiver/agents/dds/dds_transport.h"
#include "quiver/agents/replication/replicator.h"
#include "quiver/graph/graph.h"

namespace quiver::agents {

struct DdsReplicaOptions {
  std::string name;                ///< the agent id is derived from it (FNV-1a)
  bool observer = false;           ///< read-only replica (e.g. `quiver dump`)
  std::uint64_t incarnation = 0;   ///< 0: a fresh one (see fresh_incarnation())
  DdsConfig dds;
  ReplicatorOptions replicator;    ///< name and observer are taken from above
  std::int64_t tick_ns = 10'000'000;
};

/// A new incarnation number for a process start: microseconds of the wall clock shifted left
/// 12 bits, plus 12 random bits. Later starts get larger numbers (so peers replace an old
/// incarnation by a new one), and two starts in the same microsecond still differ.
std::uint64_t fresh_incarnation();

/// Monotonic time in nanoseconds (the agent's clock).
std::int64_t monotonic_ns();

class DdsReplica {
 public:
  static Result<std::unique_ptr<DdsReplica>> create(DdsReplicaOptions options);
  /// Leaves cleanly: peers see this replica go at once.
  ~DdsReplica();
  DdsReplica(const DdsReplica&) = delete;
  DdsReplica& operator=(const DdsReplica&) = delete;

  graph::Graph& graph() { return *graph_; }
  Replicator& replicator() { return *replicator_; }
  DdsTransport& transport() { return *transport_; }
  const DdsReplicaOptions& options() const { return opt_; }
  const PeerId& id() const { return graph_->replica(); }

  /// One round of the loop: waits up to `max_wait_ns` for traffic (less if a timer is due),
  /// handles what arrived, runs posted tasks and timers.
  void spin_once(std::int64_t max_wait_ns);
  /// Spins until `done()` holds (checked after every round) or `timeout_ns` passes.
  bool spin_until(const std::function<bool()>& done, std::int64_t timeout_ns);
  void spin_for(std::int64_t duration_ns);
  /// Spins until stop() is called.
  void spin();

  /// Thread-safe: runs `fn` on the owner thread at its next round.
  void post(std::function<void()> fn);
  /// Thread-safe: makes spin() return.
  void stop();

 private:
  DdsReplica() = default;
  DdsReplicaOptions opt_;
  std::unique_ptr<graph::Graph> graph_;
  std::unique_ptr<DdsTransport> transport_;
  std::unique_ptr<Replicator> replicator_;
  std::int64_t next_tick_ = 0;
  std::mutex mu_;
  std::vector<std::function<void()>> posted_;  // guarded by mu_
  std::atomic<bool> stop_{false};
};

}  // namespace quiver::agents
