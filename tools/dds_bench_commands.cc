// quiver bench dds / dds-tracking (multi-process benchmarks of the DDS transport) and the hidden
// bench-dds-role command (one process of them): their options; the coordinators and the roles
// are tools/bench's (quiver_bench).
#include "quiver/tools/bench/dds_bench.h"

#include <unistd.h>

#include <memory>
#include <string>

#include "commands.h"
#include "dds_options.h"
#include "quiver/tools/bench/dds_roles.h"
#include "quiver/tools/bench/dds_scale_bench.h"
#include "quiver/tools/bench/scale_roles.h"
#include "quiver/tools/bench/tracking_bench.h"

namespace quiver::tools {
namespace {

// This executable: the roles run as its `bench-dds-role` command, the viewer as its `view`.
std::string self_exe() {
  char buf[4096];
  ssize_t n = readlink("/proc/self/exe", buf, sizeof buf - 1);
  return n > 0 ? std::string(buf, static_cast<std::size_t>(n)) : "quiver";
}

struct BenchFlags {
  DdsFlags dds;
  bench::DdsBench dds_bench;
  bench::TrackingBench tracking;
  bench::DdsScaleBench scale;
};

struct RoleFlags {
  DdsFlags dds;
  bench::DdsRole role;
  bool transport_only = false;  ///< DDS Security without signed deltas and permissions
  long changes = 1000;          ///< scale roles
  double rate = 10;
  double idle_s = 10;
  double settle_s = 2;
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
    run.roles = {self_exe(), f->dds};
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
    run.roles = {self_exe(), f->dds};
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
    run.roles = {self_exe(), f->dds};
    set_exit_code(bench::run_dds_scale_bench(run));
  });

  auto r = std::make_shared<RoleFlags>();
  bench::DdsRole& o = r->role;
  auto* role = app.add_subcommand("bench-dds-role", "internal: one process of a DDS benchmark");
  role->group("");  // hidden
  role->add_option("role", o.role)->required();
  r->dds.add_to(role);
  role->add_option("--id", o.id)->check(CLI::Range(0, 1000));
  role->add_option("--readers", o.readers)->check(CLI::Range(1, 64));
  role->add_option("--updates", o.updates)->check(CLI::Range(1L, 1'000'000'000L));
  role->add_option("--batch", o.batch)->check(CLI::Range(1, 100000));
  role->add_option("--latency-samples", o.latency_samples)->check(CLI::Range(0, 10'000'000));
  role->add_option("--join-nodes", o.join_nodes)->check(CLI::Range(0, 10'000'000));
  role->add_option("--agents", o.agents)->check(CLI::Range(2, 120));
  role->add_option("--seconds", o.seconds)->check(CLI::Range(0.1, 3600.0));
  role->add_flag("--transport-only", r->transport_only);
  role->add_flag("--stages", o.stages);
  role->add_option("--changes", r->changes)->check(CLI::Range(1L, 10'000'000L));
  role->add_option("--rate", r->rate)->check(CLI::Range(0.1, 100000.0));
  role->add_option("--idle", r->idle_s)->check(CLI::Range(1.0, 3600.0));
  role->add_option("--settle", r->settle_s)->check(CLI::Range(0.0, 3600.0));
  role->callback([r] {
    if (r->transport_only) r->dds.graph_security = false;
    if (r->role.role.rfind("scale-", 0) == 0) {
      bench::ScaleRole s{r->role.role, nullptr, r->role.id, r->role.agents, r->changes, r->rate, r->idle_s, r->settle_s};
      s.open = [dds = r->dds](agents::DdsReplicaOptions opts) { return dds.create_agent(std::move(opts)); };
      set_exit_code(bench::run_scale_role(s));
      return;
    }
    bench::DdsRole run = r->role;
    run.open = [dds = r->dds](agents::DdsReplicaOptions opts) {
      return dds.create_agent(std::move(opts));
    };
    set_exit_code(bench::run_dds_role(run));
  });
}

}  // namespace quiver::tools
