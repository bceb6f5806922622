// quiver bench, quiver bench crdt, load, memory, footprint, all and scale: their options; the runs are tools/bench's
// (quiver_bench).
#include <functional>
#include <memory>

#include "commands.h"
#include "quiver/tools/bench/all_bench.h"
#include "quiver/tools/bench/crdt_bench.h"
#include "quiver/tools/bench/load_bench.h"
#include "quiver/agents/runtime/process/subprocess.h"
#include "quiver/tools/bench/footprint_bench.h"
#include "quiver/tools/bench/memory_bench.h"
#include "quiver/tools/bench/scale_bench.h"
#include "quiver/tools/bench/team_bench.h"
#include "quiver/tools/bench/schedules_bench.h"

namespace quiver::tools {
namespace {

// A command's callback: runs `run` on a copy of the options, with `quiver` set to this executable
// (the benchmarks that start other processes find their executables beside it).
template <class Options>
std::function<void()> with_this_executable(std::shared_ptr<Options> options, int (*run)(const Options&)) {
  return [options, run] {
    Options o = *options;
    o.quiver = agents::self_executable();
    set_exit_code(run(o));
  };
}

}  // namespace

void add_bench_commands(CLI::App& app) {
  auto* bench = app.add_subcommand("bench", "Benchmarks (one JSON line per result)");
  auto b = std::make_shared<bench::CrdtBench>();
  auto* crdt =
      bench->add_subcommand("crdt", "CRDT core: random attribute writes, encode, decode and apply");
  crdt->add_option("--nodes", b->nodes)->check(CLI::Range(1, 10'000'000))->capture_default_str();
  crdt->add_option("--attrs", b->attrs)->check(CLI::Range(1, 1000))->capture_default_str();
  crdt->add_option("--updates", b->updates)
      ->check(CLI::Range(1L, 1'000'000'000L))
      ->capture_default_str();
  crdt->add_option("--batch", b->batch)->check(CLI::Range(1, 1'000'000))->capture_default_str();
  crdt->add_option("--seed", b->seed)->check(CLI::NonNegativeNumber)->capture_default_str();
  crdt->add_flag("--events", b->events, "subscribe to change events on the receiving replica");
  crdt->callback([b] { set_exit_code(bench::run_crdt_bench(*b)); });
  auto l = std::make_shared<bench::LoadBench>();
  auto* load = bench->add_subcommand(
      "load",
      "One large transaction: an RT chain built, committed, decoded and merged; "
      "and the same chain loaded from a world file");
  load->add_option("--frames", l->frames)->check(CLI::Range(2, 10'000'000))->capture_default_str();
  load->add_option("--runs", l->runs)->check(CLI::Range(1, 1000))->capture_default_str();
  load->callback([l] { set_exit_code(bench::run_load_bench(*l)); });
  auto mb = std::make_shared<bench::MemoryBench>();
  auto* memory = bench->add_subcommand(
      "memory",
      "Heap bytes a replica holds per node, attribute and edge, beside the payload (default: CORTEX's representative "
      "node, 10 attributes and 3 edges of 2 attributes)");
  memory->add_option("--nodes", mb->nodes)->check(CLI::Range(2, 10'000'000))->capture_default_str();
  memory->add_option("--attrs", mb->attrs, "attributes per node")->check(CLI::Range(0, 1000))->capture_default_str();
  memory->add_option("--edges", mb->edges, "edges per node")->check(CLI::Range(0, 100))->capture_default_str();
  memory->add_option("--edge-attrs", mb->edge_attrs, "attributes per edge")->check(CLI::Range(0, 100))->capture_default_str();
  memory->add_option("--runs", mb->runs)->check(CLI::Range(1, 100))->capture_default_str();
  memory->add_option("--seed", mb->seed)->check(CLI::NonNegativeNumber)->capture_default_str();
  memory->callback([mb] { set_exit_code(bench::run_memory_bench(*mb)); });
  auto ab = std::make_shared<bench::AllBench>();
  auto* all = bench->add_subcommand(
      "all",
      "Every benchmark beside its peer in one run (ddsperf, Yjs through node where installed, tf2): OUT/bench.json and "
      "OUT/index.html with the plots");
  all->add_option("--out", ab->out, "the report's folder (default: a new /tmp/quiver-bench-all-*)");
  all->add_flag("--quick", ab->quick, "small sizes: checks that every benchmark runs (about a minute), not figures to quote");
  all->add_option("--domain", ab->domain, "DDS domain of the DDS benchmarks and ddsperf (loopback; the next one too)")
      ->check(CLI::Range(0, 229))
      ->capture_default_str();
  all->callback(with_this_executable(ab, bench::run_all_bench));
  auto fb = std::make_shared<bench::FootprintBench>();
  auto* footprint = bench->add_subcommand(
      "footprint",
      "Resident memory and mapped libraries of agent processes at rest: quiver agent (the lean quiver-agent), the same "
      "inside the whole quiver, each Barthel role in quiver-barthel");
  footprint->add_option("--world", fb->world,
                        "quiver agent's world file (default: examples/worlds/kitchen.json when it is there, else none)")
      ->check(CLI::ExistingFile);
  footprint->add_option("--runs", fb->runs, "processes per variant (medians)")->check(CLI::Range(1, 100))->capture_default_str();
  footprint->add_option("--settle", fb->settle_s, "seconds after the start when a process is measured")
      ->check(CLI::Range(0.5, 600.0))
      ->capture_default_str();
  footprint->add_option("--domain", fb->domain, "DDS domain (loopback)")->check(CLI::Range(0, 230))->capture_default_str();
  footprint->callback(with_this_executable(fb, bench::run_footprint_bench));
  auto sc = std::make_shared<bench::ScaleBench>();
  auto* scale = bench->add_subcommand(
      "scale",
      "What each agent pays as agents are added: `quiver sim --agents N` for each N, bytes and "
      "messages per op per agent (scripts/plot_scale.py draws them)");
  scale->add_option("--agents", sc->agents, "the numbers of agents, e.g. --agents 4,8,16")
      ->delimiter(',')
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  scale->add_option("--protocol", sc->protocol,
                    "gossip (the default) or all-to-all (the protocol before issue 22, for the curve beside)")
      ->check(CLI::IsMember({"gossip", "all-to-all"}))
      ->capture_default_str();
  scale->add_flag("--no-heal", sc->skip_heal, "skip the second run of each N (a partition until the end, then the heal)");
  scale->add_option("--steps", sc->steps, "workload steps per run")
      ->check(CLI::Range(1, 10'000'000))
      ->capture_default_str();
  scale->add_option("--seed", sc->seed)->check(CLI::NonNegativeNumber)->capture_default_str();
  scale->add_option("--idle", sc->idle_s, "virtual seconds of idle traffic measured after each run")
      ->check(CLI::Range(0.05, 3600.0))
      ->capture_default_str();
  scale->callback([sc] { set_exit_code(bench::run_scale_bench(*sc)); });
  auto sb = std::make_shared<bench::SchedulesBench>();
  auto* sched = bench->add_subcommand(
      "schedules",
      "Many seeded fault schedules (loss, duplication, reordering, partitions, crashes and restarts) at one "
      "number of agents in the simulator: how many converged, diverged or broke an invariant");
  sched->add_option("--agents", sb->agents)->check(CLI::Range(1, 1000))->capture_default_str();
  sched->add_option("--count", sb->count, "schedules (seeds --seed .. --seed+count-1)")
      ->check(CLI::Range(1, 1'000'000))
      ->capture_default_str();
  sched->add_option("--seed", sb->seed)->check(CLI::NonNegativeNumber)->capture_default_str();
  sched->add_option("--steps", sb->steps, "workload steps per schedule")->check(CLI::Range(1, 1'000'000))->capture_default_str();
  sched->add_option("--max-loss", sb->max_loss, "the highest loss a schedule draws")
      ->check(CLI::Range(0.0, 0.95))
      ->capture_default_str();
  sched->add_option("--protocol", sb->protocol, "gossip (the default) or all-to-all")
      ->check(CLI::IsMember({"gossip", "all-to-all"}))
      ->capture_default_str();
  sched->callback([sb] { set_exit_code(bench::run_schedules_bench(*sb)); });
  auto tb = std::make_shared<bench::TeamBench>();
  auto* team = bench->add_subcommand(
      "team",
      "Robots as network namespaces (root only; nothing leaves them), each with its gateway: the human tracker "
      "(900 joint poses/s) on one robot, the joints' latency on the others, the bytes on the team network against "
      "the delta bytes the tracker publishes (target <= 1.5 x (robots - 1)), and a robot joining a world of --nodes "
      "nodes late (target <= 1 s); docs/teams.md");
  team->add_option("--robots", tb->robots)->check(CLI::Range(2, 8))->capture_default_str();
  team->add_option("--seconds", tb->seconds, "how long the tracker runs")->check(CLI::Range(1.0, 3600.0))->capture_default_str();
  team->add_option("--nodes", tb->nodes, "the world the late robot joins (nodes of 10 attributes)")
      ->check(CLI::Range(1, 1'000'000))
      ->capture_default_str();
  team->add_option("--out", tb->out, "keep the processes' logs in this directory");
  team->callback([tb] { set_exit_code(bench::run_team_bench(*tb)); });
}

}  // namespace quiver::tools
