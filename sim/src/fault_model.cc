// The fault model: events, their file form, and playing a schedule on a host.
#include "quiver/sim/fault_model.h"

#include <nlohmann/json.hpp>
#include <sstream>

#include "file_error.h"

namespace quiver::sim {
namespace {

using internal::file_error;

}  // namespace

std::string FaultEvent::describe() const {
  std::ostringstream o;
  o << "t=" << at_s << "s ";
  switch (kind) {
    case Kind::kPartition: {
      o << "partition";
      for (const auto& g : groups) {
        o << " {";
        for (std::size_t i = 0; i < g.size(); ++i) o << (i ? "," : "") << g[i];
        o << "}";
      }
      break;
    }
    case Kind::kHeal: o << "heal"; break;
    case Kind::kKill: o << "kill -9 " << agent; break;
    case Kind::kRestart: o << "restart " << agent; break;
    case Kind::kLoss: o << "loss " << loss; break;
  }
  return o.str();
}

Result<FaultEvent> parse_fault(const nlohmann::json& f, const std::string& source, const std::string& where,
                               const std::function<bool(const std::string&)>& is_agent) {
  if (!f.is_object() || !f.contains("at_s") || !f["at_s"].is_number() || f["at_s"].get<double>() < 0)
    return file_error(source, where, "expected {\"at_s\": T >= 0, and one of partition, heal, kill, restart, loss}");
  FaultEvent e;
  e.at_s = f["at_s"].get<double>();
  if (f.contains("partition")) {
    e.kind = FaultEvent::Kind::kPartition;
    const nlohmann::json& gs = f["partition"];
    if (!gs.is_array() || gs.empty()) return file_error(source, where + "/partition", "expected groups of agent names");
    for (std::size_t g = 0; g < gs.size(); ++g) {
      if (!gs[g].is_array()) return file_error(source, where + "/partition/" + std::to_string(g), "expected an array of names");
      std::vector<std::string> group;
      for (std::size_t k = 0; k < gs[g].size(); ++k) {
        if (!gs[g][k].is_string() || !is_agent(gs[g][k].get<std::string>()))
          return file_error(source, where + "/partition/" + std::to_string(g) + "/" + std::to_string(k), "not an agent");
        group.push_back(gs[g][k].get<std::string>());
      }
      e.groups.push_back(group);
    }
  } else if (f.contains("heal")) {
    e.kind = FaultEvent::Kind::kHeal;
  } else if (f.contains("kill") || f.contains("restart")) {
    const bool kill = f.contains("kill");
    e.kind = kill ? FaultEvent::Kind::kKill : FaultEvent::Kind::kRestart;
    const nlohmann::json& a = f[kill ? "kill" : "restart"];
    if (!a.is_string() || !is_agent(a.get<std::string>()))
      return file_error(source, where + (kill ? "/kill" : "/restart"), "not an agent");
    e.agent = a.get<std::string>();
  } else if (f.contains("loss")) {
    e.kind = FaultEvent::Kind::kLoss;
    if (!f["loss"].is_number() || f["loss"].get<double>() < 0 || f["loss"].get<double>() > 0.9)
      return file_error(source, where + "/loss", "expected a probability in [0, 0.9]");
    e.loss = f["loss"].get<double>();
  } else {
    return file_error(source, where, "no fault (partition, heal, kill, restart or loss)");
  }
  return e;
}

nlohmann::json to_json(const FaultEvent& f) {
  nlohmann::json e = {{"at_s", f.at_s}};
  switch (f.kind) {
    case FaultEvent::Kind::kPartition: e["partition"] = f.groups; break;
    case FaultEvent::Kind::kHeal: e["heal"] = true; break;
    case FaultEvent::Kind::kKill: e["kill"] = f.agent; break;
    case FaultEvent::Kind::kRestart: e["restart"] = f.agent; break;
    case FaultEvent::Kind::kLoss: e["loss"] = f.loss; break;
  }
  return e;
}

void schedule_faults(FaultTarget& target, const std::vector<FaultEvent>& faults,
                     std::function<void(std::int64_t, const std::string&)> log, FaultCounts& counts) {
  for (const FaultEvent& f : faults) {
    target.at(static_cast<std::int64_t>(f.at_s * 1e9), [&target, &counts, f, log] {
      if (log) log(target.now(), "fault: " + f.describe());
      switch (f.kind) {
        case FaultEvent::Kind::kPartition:
          target.partition(f.groups);
          ++counts.partitions;
          break;
        case FaultEvent::Kind::kHeal: target.heal(); break;
        case FaultEvent::Kind::kKill:
          if (target.kill(f.agent)) ++counts.kills;
          break;
        case FaultEvent::Kind::kRestart:
          if (target.restart(f.agent)) ++counts.restarts;
          break;
        case FaultEvent::Kind::kLoss: target.set_loss(f.loss); break;
      }
    });
  }
}

}  // namespace quiver::sim
