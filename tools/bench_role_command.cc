// The hidden bench-dds-role command: one process of a DDS benchmark (`quiver bench dds`,
// `dds-tracking`, `dds-scale`). It lives with the agent's commands, so that the lean quiver-agent
// runs the roles (the benchmarks start it when it is beside quiver): a benchmark agent then maps
// what an agent maps, not the whole CLI.
#include <memory>
#include <string>

#include "commands.h"
#include "dds_options.h"
#include "quiver/tools/bench/dds_roles.h"
#include "quiver/tools/bench/scale_roles.h"

namespace quiver::tools {
namespace {

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

void add_bench_role_command(CLI::App& app) {
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
    const auto open = [dds = r->dds](agents::DdsReplicaOptions opts) { return dds.create_agent(std::move(opts)); };
    if (r->role.role.rfind("scale-", 0) == 0) {
      bench::ScaleRole s{r->role.role, open, r->role.id, r->role.agents, r->changes, r->rate, r->idle_s, r->settle_s};
      set_exit_code(bench::run_scale_role(s));
      return;
    }
    bench::DdsRole run = r->role;
    run.open = open;
    set_exit_code(bench::run_dds_role(run));
  });
}

}  // namespace quiver::tools
