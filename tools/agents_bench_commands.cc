// quiver bench grammar, quiver bench locks: their options; the runs are tools/bench's
// (quiver_bench).
#include <memory>

#include "commands.h"
#include "quiver/tools/bench/grammar_bench.h"
#include "quiver/tools/bench/lock_bench.h"

namespace quiver::tools {

void add_agents_bench_commands(CLI::App& app) {
  CLI::App* bench = app.get_subcommand("bench");
  auto g =
      bench->add_subcommand("grammar", "Grammar check cost per transaction (50 rules, 10k nodes)");
  auto gb = std::make_shared<bench::GrammarBench>();
  g->add_option("--nodes", gb->nodes)->check(CLI::Range(1, 10'000'000))->capture_default_str();
  g->add_option("--rules", gb->rules)->check(CLI::Range(1, 100'000))->capture_default_str();
  g->add_option("--checks", gb->checks)->check(CLI::Range(1, 100'000'000))->capture_default_str();
  g->add_flag("--agm", gb->agm,
              "the same rules in AGM's dialect, each with an effect (a forall over what v0 "
              "carries, anchored on v0)");
  g->callback([gb] { set_exit_code(bench::run_grammar_bench(*gb)); });

  auto l = bench->add_subcommand("locks",
                                 "Lock acquire latency: in the simulator and over DDS (loopback)");
  auto lb = std::make_shared<bench::LockBench>();
  l->add_option("--agents", lb->agents)->check(CLI::Range(2, 16))->capture_default_str();
  l->add_option("--rounds", lb->rounds)->check(CLI::Range(1, 1'000'000))->capture_default_str();
  l->add_option("--domain", lb->domain)->check(CLI::Range(0, 230))->capture_default_str();
  l->callback([lb] { set_exit_code(bench::run_lock_bench(*lb)); });
}

}  // namespace quiver::tools
