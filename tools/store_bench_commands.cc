// quiver bench store (what the durable store costs, docs/persistence.md): its options; the run is
// tools/bench's (quiver_bench).
#include "quiver/tools/bench/store_bench.h"

#include <memory>

#include "commands.h"

namespace quiver::tools {

void add_store_bench_command(CLI::App& app) {
  CLI::App* bench = app.get_subcommand("bench");
  auto b = std::make_shared<bench::StoreBench>();
  auto* s = bench->add_subcommand(
      "store",
      "The durable store: the bench crdt write rate without and with a store under "
      "each durability, and the reload time of a large replica");
  s->add_option("--nodes", b->nodes)->check(CLI::Range(1, 10'000'000))->capture_default_str();
  s->add_option("--attrs", b->attrs)->check(CLI::Range(1, 1000))->capture_default_str();
  s->add_option("--updates", b->updates)
      ->check(CLI::Range(1L, 1'000'000'000L))
      ->capture_default_str();
  s->add_option("--batch", b->batch)->check(CLI::Range(1, 1'000'000))->capture_default_str();
  s->add_option("--runs", b->runs, "rounds (medians are reported)")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  s->add_option("--reload-nodes", b->reload_nodes)
      ->check(CLI::Range(1, 10'000'000))
      ->capture_default_str();
  s->add_option("--dir", b->dir,
                "make the stores here (default: a new folder in /tmp, removed after)");
  s->callback([b] { set_exit_code(bench::run_store_bench(*b)); });
}

}  // namespace quiver::tools
