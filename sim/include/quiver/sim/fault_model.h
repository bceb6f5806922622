#pragma once
/// @file
/// The simulator's one fault model: a schedule of fault events at virtual times (partition, heal,
/// kill -9, restart, packet loss), as scenario files state them and as the random generator
/// (fault_generator.h) draws them, played on whatever hosts the agents (FaultTarget): the agent
/// host of scenarios, or the replica simulator of `quiver sim`.
///
/// Threading: the simulator's one thread.

#include <cstdint>
#include <functional>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "quiver/base/result.h"

namespace quiver::sim {

struct FaultEvent {
  enum class Kind : std::uint8_t { kPartition, kHeal, kKill, kRestart, kLoss } kind = Kind::kHeal;
  double at_s = 0;
  std::vector<std::vector<std::string>> groups;  ///< kPartition: agents by name; the others form one more group
  std::string agent;                             ///< kKill, kRestart
  double loss = 0;                               ///< kLoss: probability a sample is dropped on a link
  /// "t=3s partition {a,b} {c}", "t=9s kill -9 planner", ...
  std::string describe() const;
};

/// Reads one event of a scenario file ({"at_s": T, and one of "partition": [[names]...],
/// "heal": true, "kill": name, "restart": name, "loss": p}). `is_agent` says which names are
/// agents of the scenario. @returns kInvalidArgument naming `source`, the JSON pointer `where` and
/// the bad value.
Result<FaultEvent> parse_fault(const nlohmann::json& j, const std::string& source, const std::string& where,
                               const std::function<bool(const std::string&)>& is_agent);
/// The event as a scenario file writes it.
nlohmann::json to_json(const FaultEvent& e);

/// What plays a fault schedule: a host of agents known by name.
class FaultTarget {
 public:
  virtual ~FaultTarget() = default;
  /// Virtual time now, and a call at `t_ns` (now if earlier).
  virtual std::int64_t now() const = 0;
  virtual void at(std::int64_t t_ns, std::function<void()> fn) = 0;
  /// Agents hear each other only within a group; agents not named form one more group.
  virtual void partition(const std::vector<std::vector<std::string>>& groups) = 0;
  virtual void heal() = 0;
  /// kill -9 of a running agent. @returns false when it was not running (nothing happened).
  virtual bool kill(const std::string& agent) = 0;
  /// Starts a stopped agent again (a fresh incarnation). @returns false when it was running.
  virtual bool restart(const std::string& agent) = 0;
  virtual void set_loss(double p) = 0;
};

/// Counts of the faults that took effect (a kill of an agent already down does not count).
struct FaultCounts {
  int partitions = 0, kills = 0, restarts = 0;
};

/// Schedules every event of `faults` on `target` (its clock). Each is logged through `log` (may
/// be null) when it happens; `counts` (which must outlive the run) counts those that took effect.
void schedule_faults(FaultTarget& target, const std::vector<FaultEvent>& faults,
                     std::function<void(std::int64_t, const std::string&)> log, FaultCounts& counts);

}  // namespace quiver::sim
