// quiver bench reaction: how fast Speech stops talking when the person leaves. The Barthel agents
// run as one process each over DDS on loopback; the simulated patient leaves the chair in the
// middle of the first question again and again. Each time, Person commits the loss
// (person.lost_ns, on the machine's monotonic clock that every process shares) and Speech stops
// the audio when the change reaches it; Speech records the difference.
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <set>
#include <thread>

#include "quiver/agents/apps/barthel/barthel_roles.h"
#include "quiver/agents/apps/barthel/barthel_schema.h"
#include "quiver/agents/apps/barthel/grammars.h"
#include "quiver/agents/apps/barthel/process/barthel_runs.h"
#include "quiver/agents/runtime/process/logging.h"
#include "quiver/agents/runtime/process/observer_replica.h"
#include "quiver/base/percentiles.h"

namespace quiver::agents::inline apps::barthel {
namespace {

using nlohmann::json;
using base::median;
using base::Percentiles;
using base::round_to;

// A patient who answers every question by voice but leaves mid-question `n` times on the first item.
PatientScript restless_patient(const ReactionBench& f) {
  PatientScript s = PatientScript::random(1);
  for (auto& it : s.items) it.first = it.second = {ReplyKind::kVoice, 0};
  s.leaves.clear();
  for (int i = 0; i < f.leaves; ++i)
    s.leaves.push_back({0, static_cast<std::int64_t>(f.leave_after_ms * 1e6), static_cast<std::int64_t>(f.away_ms * 1e6)});
  return s;
}

std::string make_dir(const std::string& base, int run) {
  if (!base.empty()) {
    const std::string d = base + "/run-" + std::to_string(run);
    ::mkdir(base.c_str(), 0755);
    ::mkdir(d.c_str(), 0755);
    return d;
  }
  char tmpl[] = "/tmp/quiver-reaction-XXXXXX";
  return mkdtemp(tmpl) ? std::string(tmpl) : std::string();
}

// One run: the reactions Speech measured, in milliseconds (empty when the run could not start).
std::vector<double> one_run(const ReactionBench& f, int run, std::string& dir) {
  dir = make_dir(f.out, run);
  if (dir.empty()) return {};
  const std::string script_path = dir + "/patient.json";
  std::ofstream(script_path) << restless_patient(f).to_json().dump(1) << "\n";

  auto obs = open_observer_replica(f.observer, "reaction-observer", "quiver bench reaction", world_json());
  if (!obs) return {};
  BarthelProcessOptions po = f.processes;
  po.out = dir;
  po.script_path = script_path;
  po.answer_timeout_s = 8;
  po.simulated_speech = true;
  BarthelProcesses procs(po);
  for (const auto& r : role_names())
    if (!procs.start(r)) return {};

  // Watch the losses Person commits until the patient has left `leaves` times and come back.
  std::set<std::int64_t> losses;
  const graph::Graph& g = obs->graph();
  const auto t0 = std::chrono::steady_clock::now();
  const double limit_s = 30 + f.leaves * 6.0;
  std::int64_t done_at = -1;
  for (;;) {
    obs->spin_once(20'000'000);
    const graph::NodeId person = node_id(g, node::kPerson);
    if (const std::int64_t lost = attr_int(g, person, "lost_ns", 0); lost > 0) losses.insert(lost);
    const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (done_at < 0 && static_cast<int>(losses.size()) >= f.leaves && person_present(g)) done_at = monotonic_ns();
    if (done_at >= 0 && monotonic_ns() - done_at > 500'000'000) break;
    if (t > limit_s) {
      named_logger("quiver bench reaction")->warn("run {} saw {} of {} losses in {:.0f} s; stopping", run, losses.size(), f.leaves, limit_s);
      break;
    }
  }
  procs.stop_all();
  std::vector<double> ms;
  if (auto st = procs.last_status("speech"); st && st->contains("reactions_us"))
    for (const auto& v : (*st)["reactions_us"]) ms.push_back(v.get<double>() / 1e3);
  return ms;
}

}  // namespace

int run_reaction_bench(const ReactionBench& f) {
  std::vector<double> p50s, p99s;
  for (int run = 0; run < f.runs; ++run) {
    std::string dir;
    const std::vector<double> ms = one_run(f, run, dir);
    const Percentiles pct(ms);
    json j = {{"bench", "reaction"}, {"run", run}, {"leaves", f.leaves}, {"reactions", ms.size()},
              {"p50_ms", round_to(pct.at(0.5), 3)}, {"p99_ms", round_to(pct.at(0.99), 3)},
              {"max_ms", round_to(pct.at(1.0), 3)}, {"out", dir}};
    std::cout << j.dump() << std::endl;
    if (ms.empty()) return 1;
    p50s.push_back(pct.at(0.5));
    p99s.push_back(pct.at(0.99));
  }
  json s = {{"bench", "reaction"}, {"runs", f.runs}, {"transport", "dds-loopback"},
            {"p50_ms_median", round_to(median(p50s), 3)}, {"p99_ms_median", round_to(median(p99s), 3)},
            {"target_p50_ms", 5}, {"target_p99_ms", 50}};
  std::cout << s.dump() << std::endl;
  return 0;
}

}  // namespace quiver::agents::inline apps::barthel
