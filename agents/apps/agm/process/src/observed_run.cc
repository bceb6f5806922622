// The observer of the AGM runs over DDS, and the agents' final status lines checked.
#include "observed_run.h"

#include <cstdio>

#include "quiver/agents/apps/agm/agm_schema.h"
#include "quiver/agents/runtime/process/logging.h"
#include "quiver/agents/runtime/process/observer_replica.h"

namespace quiver::agents::inline apps::agm {
namespace internal {

std::unique_ptr<ObservedRun> ObservedRun::open(const AgmDdsRun& r, const char* prefix, std::string_view world) {
  auto replica = open_observer_replica(r.observer, "agm-observer", "quiver scenario", world);
  if (!replica) return nullptr;
  auto run = std::make_unique<ObservedRun>();
  run->replica_ = std::move(replica);
  run->options_ = r.processes;
  run->options_.out = out_dir(r.processes.out, prefix);
  run->t_start_ = monotonic_ns();
  return run;
}

double ObservedRun::elapsed() const { return static_cast<double>(monotonic_ns() - t_start_) / 1e9; }

void ObservedRun::watch(std::function<void(graph::NodeId, const graph::EdgeChange&)> on_edge,
                        std::function<void()> on_batch) {
  graph::Graph& g = graph();
  g.subscribe([&g, on_edge = std::move(on_edge),
               on_batch = std::move(on_batch)](const graph::ChangeBatch& b) {
    const graph::NodeId robot = node_id(g, node::kRobot);
    if (robot.is_null()) return;
    for (const graph::EdgeChange& e : b.edges)
      if (e.key.from == robot) on_edge(robot, e);
    if (on_batch) on_batch();
  });
}

void ObservedRun::say(const std::string& line) const {
  std::printf("[%6.2f s] %s\n", elapsed(), line.c_str());
  std::fflush(stdout);
}

bool ObservedRun::start(
    const std::string& what, const std::string& who,
    const std::vector<std::pair<std::string, std::vector<std::string>>>& agents) {
  std::printf(
      "%s over Cyclone DDS (domain %u, loopback): %s, one process each, no executive.\nLogs: "
      "%s/logs/\n\n",
      what.c_str(), options_.dds.domain, who.c_str(), options_.out.c_str());
  procs_ = std::make_unique<AgmProcesses>(options_);
  for (const auto& [role, args] : agents)
    if (!procs_->start(role, args)) {
      named_logger("quiver scenario")->error("cannot start {} run ROLE", options_.exe);
      return false;
    }
  return true;
}

std::map<std::string, nlohmann::json> ObservedRun::stop(const std::vector<std::string>& roles,
                                                        std::optional<nlohmann::json>& humans) {
  humans = procs_->stop("humans");
  replica_->spin_for(500 * kMs);
  std::map<std::string, nlohmann::json> finals;
  for (const std::string& role : roles)
    if (auto st = procs_->stop(role)) finals[role] = *st;
  replica_->spin_for(500 * kMs);
  return finals;
}

int ObservedRun::verdict(const std::vector<std::string>& failures, const char* passed) {
  for (const auto& d : failures) std::printf("  FAILED: %s\n", d.c_str());
  std::printf("%s\n", failures.empty() ? passed : "The run FAILED its checks.");
  return failures.empty() ? 0 : 1;
}

std::vector<std::string> final_status_failures(std::map<std::string, nlohmann::json>& finals,
                                               const std::string& digest, std::size_t expected,
                                               const std::optional<nlohmann::json>& humans,
                                               bool& equal) {
  std::vector<std::string> f;
  equal = finals.size() == expected;
  for (const auto& [role, st] : finals)
    if (st.value("digest", "") != digest) {
      f.push_back(role + "'s replica differs from the observer's at the end");
      equal = false;
    }
  if (finals.size() != expected) f.push_back("not every agent reported its final state");
  if (humans) finals["humans"] = *humans;
  for (const auto& [role, st] : finals)
    if (st.value("exit_status", -1) != 0)
      f.push_back(role + " exited with status " + std::to_string(st.value("exit_status", -1)));
  return f;
}

}  // namespace internal

int run_agm_over_dds(const AgmDdsRun& r) {
  return r.mission == kCleanTable ? internal::run_clean_table(r) : internal::run_route(r);
}

}  // namespace quiver::agents::inline apps::agm
