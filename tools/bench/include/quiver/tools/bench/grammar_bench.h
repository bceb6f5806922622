#pragma once
// The grammar benchmark (`quiver bench grammar`): what checking a transaction against a synthetic
// grammar costs, in Quiver's dialect or AGM's.

namespace quiver::tools::bench {

struct GrammarBench {
  int nodes = 10000;   ///< the graph grows to this many nodes (instances of the rules' patterns)
  int rules = 50;      ///< rules of the synthetic grammar
  int checks = 20000;  ///< transactions checked
  /// The same rules in AGM's dialect, each with an effect (a forall over what v0 carries,
  /// anchored on v0).
  bool agm = false;
};

/// Checks `checks` transactions that apply a random rule (and as many that only set an
/// attribute) against a synthetic grammar of `rules` rules on a graph of `nodes` nodes made of
/// the rules' left-hand sides. Prints one JSON line on stdout (check time p50/p99, the attribute
/// transaction's p50, how many were accepted).
/// @pre every count of `b` is at least 1.
/// @returns the exit status: 0 when every rule application is accepted and every attribute
/// transaction too, 1 if not, 2 when the synthetic grammar does not parse.
int run_grammar_bench(const GrammarBench& b);

}  // namespace quiver::tools::bench
