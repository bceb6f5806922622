#include "quiver/sim/fault_schedule.h"

namespace quiver::sim {

void schedule_faults(AgentHost& host, const std::vector<FaultEvent>& faults,
                     std::function<void(std::int64_t, const std::string&)> log, int& partitions, int& kills) {
  for (const FaultEvent& f : faults) {
    host.at(static_cast<std::int64_t>(f.at_s * 1e9), [&host, &partitions, &kills, f, log] {
      if (log) log(host.now(), "fault: " + f.describe());
      switch (f.kind) {
        case FaultEvent::Kind::kPartition:
          host.partition(f.groups);
          ++partitions;
          break;
        case FaultEvent::Kind::kHeal:
          host.heal();
          break;
        case FaultEvent::Kind::kKill:
          if (int i = host.index(f.agent); i >= 0 && host.up(i)) {
            host.kill(i);
            ++kills;
          }
          break;
        case FaultEvent::Kind::kRestart:
          if (int i = host.index(f.agent); i >= 0 && !host.up(i)) host.restart(i);
          break;
        case FaultEvent::Kind::kLoss:
          host.set_loss(f.loss);
          break;
      }
    });
  }
}

}  // namespace quiver::sim
