// quiver bench dds / dds-tracking / dds-scale (multi-process benchmarks of the DDS transport):
// their options; the coordinators and the roles are tools/bench's (quiver_bench), and the role
// processes run the hidden bench-dds-role command (bench_role_command.cc) of quiver-agent.
#include "quiver/tools/bench/dds_bench.h"

#include <memory>
#include <string>

#include "commands.h"
#include "dds_options.h"
#include "quiver/agents/runtime/process/subprocess.h"
#include "quiver/tools/bench/dds_scale_bench.h"
#include "quiver/tools/bench/tracking_bench.h"

namespace quiver::tools {
namespace {

// The roles run as the `bench-dds-role` command of quiver-agent when it is beside this executable
// (of this one otherwise), the viewer as this one's `view`.
bench::RoleCommand role_command(const DdsFlags& dds) {
  return {agents::sibling_or_self("quiver-agent"), dds, agents::self_executable()};
}

struct BenchFlags {
  DdsFlags dds;
  bench::DdsBench dds_bench;
  bench::TrackingBench tracking;
  bench::DdsScaleBench scale;
};

}  // namespace

void add_dds_bench_commands(CLI::App& app) {
  auto f = std::make_shared<BenchFlags>();
  f->dds.domain = 77;
  CLI::App* bench = app.get_subcommand("bench");
  bench::DdsBench& d = f->dds_bench;
  auto* dds =
      bench->add_subcommand("dds", "DDS transport: one writer and K reader processes on loopback");
  f->dds.add_to(dds);
  dds->add_option("--updates", d.updates)
      ->check(CLI::Range(1L, 1'000'000'000L))
      ->capture_default_str();
  dds->add_option("--batch", d.batch)->check(CLI::Range(1, 100000))->capture_default_str();
  dds->add_option("--readers", d.readers)->check(CLI::Range(1, 64))->capture_default_str();
  dds->add_option("--latency-samples", d.latency_samples)
      ->check(CLI::Range(0, 10'000'000))
      ->capture_default_str();
  dds->add_option("--join-nodes", d.join_nodes)
      ->check(CLI::Range(0, 10'000'000))
      ->capture_default_str();
  dds->add_flag(
      "--with-viewer", d.with_viewer,
      "run `quiver view` on the domain, with a page's event stream open, during the benchmark");
  dds->add_flag("--viewer-every-delta", d.viewer_every_delta,
                "the viewer reads every delta (`quiver view --every-delta`)");
  dds->add_flag("--secure", d.secure,
                "DDS Security and signed, policy-checked deltas: every role gets an identity from "
                "a fresh CA in a "
                "temporary directory (docs/security.md)");
  dds->add_flag("--secure-transport", d.secure_transport,
                "DDS Security alone, as --secure but without signed deltas and graph-level "
                "permissions: what each "
                "layer costs");
  dds->add_flag("--stages", d.stages,
                "with the latency phase, where each change's time goes: commit and encode, sign, "
                "DDS write, delivery and wake-up, take, decode, admission, merge and events "
                "(medians, stages_us_p50)");
  dds->callback([f] {
    bench::DdsBench run = f->dds_bench;
    run.roles = role_command(f->dds);
    set_exit_code(bench::run_dds_bench(run));
  });

  bench::TrackingBench& t = f->tracking;
  auto* tr = bench->add_subcommand(
      "dds-tracking",
      "DDS transport: the AGM human-tracking load (2 people x 15 joints x 30 Hz) to N-1 agents");
  f->dds.add_to(tr);
  tr->add_option("--agents", t.agents)->check(CLI::Range(2, 100))->capture_default_str();
  tr->add_option("--seconds", t.seconds)->check(CLI::Range(0.1, 3600.0))->capture_default_str();
  tr->add_flag("--with-viewer", t.with_viewer,
               "run `quiver view` on the domain, with a page's event stream open");
  tr->add_flag("--viewer-every-delta", t.viewer_every_delta,
               "the viewer reads every delta (`quiver view --every-delta`)");
  tr->callback([f] {
    bench::TrackingBench run = f->tracking;
    run.roles = role_command(f->dds);
    set_exit_code(bench::run_tracking_bench(run));
  });

  bench::DdsScaleBench& sc = f->scale;
  auto* dsc = bench->add_subcommand(
      "dds-scale",
      "N agent processes over DDS (issue 22): one writes a change every 1/rate s, the others receive it; CPU "
      "per agent while changes flow and while idle; one more agent joins");
  f->dds.add_to(dsc);
  dsc->add_option("--agents", sc.agents, "the numbers of processes, e.g. --agents 2,8,32,100")
      ->delimiter(',')
      ->check(CLI::Range(2, 120))
      ->capture_default_str();
  dsc->add_option("--changes", sc.changes)->check(CLI::Range(1L, 10'000'000L))->capture_default_str();
  dsc->add_option("--rate", sc.rate, "changes per second")->check(CLI::Range(0.1, 100000.0))->capture_default_str();
  dsc->add_option("--idle", sc.idle_s, "seconds of idle time over which CPU is measured")
      ->check(CLI::Range(1.0, 3600.0))
      ->capture_default_str();
  dsc->add_option("--settle", sc.settle_s, "seconds the writer waits after every process joined, before writing")
      ->check(CLI::Range(0.0, 3600.0))
      ->capture_default_str();
  dsc->add_option("--start-gap-ms", sc.start_gap_ms,
                  "start the processes this many ms apart (many processes on few cores)")
      ->check(CLI::Range(0, 60'000))
      ->capture_default_str();
  dsc->callback([f] {
    bench::DdsScaleBench run = f->scale;
    run.roles = role_command(f->dds);
    set_exit_code(bench::run_dds_scale_bench(run));
  });
}

}  // namespace quiver::tools
