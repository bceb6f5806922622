// quiver grammar check: parse and load grammar files (our dialect or AGM's), one summary line
// each, or the error.

#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "commands.h"
#include "grammar_schema.h"
#include "quiver/agents/rules/grammar/grammar.h"

namespace quiver::tools {
namespace {

struct CheckArgs {
  std::vector<std::string> files;
  std::vector<std::string> include_dirs;
  bool notes = false;
  std::string schema;  // empty: no vocabulary check
};

std::string summary(const agents::Grammar& g, const agents::GrammarChecker& checker) {
  int active = 0, passive = 0, hierarchical = 0, combos = 0, dormant = 0, preconditions = 0,
      effects = 0;
  for (const agents::Rule& r : g.rules) {
    (r.active ? active : passive) += 1;
    hierarchical += r.kind == agents::Rule::Kind::kHierarchical;
    combos += r.kind == agents::Rule::Kind::kCombo;
    dormant += r.dormant;
    preconditions += r.precondition.has_value();
    effects += r.effect.has_value() || !r.foralls.empty();
  }
  std::string s =
      "grammar '" + g.name + "' (" +
      (g.dialect == agents::Grammar::Dialect::kAgm ? "AGM's dialect" : "Quiver's dialect") +
      "): " + std::to_string(g.types.names().size()) + " types, " + std::to_string(g.rules.size()) +
      " rules (" + std::to_string(active) + " active, " + std::to_string(passive) + " passive; " +
      std::to_string(hierarchical) + " hierarchical, " + std::to_string(combos) + " combos, " +
      std::to_string(dormant) + " dormant; " + std::to_string(preconditions) +
      " with preconditions, " + std::to_string(effects) + " with effects), " +
      std::to_string(g.constraints.size()) + " constraints, " + std::to_string(g.includes.size()) +
      " includes";
  const std::size_t notes = g.notes.size() + checker.notes().size();
  if (notes > 0) s += ", " + std::to_string(notes) + " notes";
  return s;
}

void run_check(const CheckArgs& a) {
  int failed = 0;
  std::optional<agents::schema::Schema> vocabulary;
  if (!a.schema.empty()) {
    auto s = agents::schema::Schema::load(a.schema);
    if (!s.ok()) {
      std::cout << "error: " << s.error().message << "\n";
      return set_exit_code(1);
    }
    vocabulary = std::move(*s);
  }
  for (const std::string& file : a.files) {
    auto g = agents::load_grammar_file(file, a.include_dirs);
    if (!g.ok()) {
      std::cout << file << ": error: " << g.error().message << "\n";
      ++failed;
      continue;
    }
    std::vector<std::string> notes = g->notes;
    if (vocabulary) {
      const auto errors = grammar_schema_errors(*g, *vocabulary);
      for (const std::string& e : errors) std::cout << file << ": error: " << e << "\n";
      if (!errors.empty()) {
        ++failed;
        continue;
      }
    }
    agents::GrammarChecker checker(std::move(*g));
    notes.insert(notes.end(), checker.notes().begin(), checker.notes().end());
    std::cout << file << ": ok: " << summary(checker.grammar(), checker) << "\n";
    if (a.notes)
      for (const std::string& n : notes) std::cout << "  note: " << n << "\n";
  }
  if (a.files.size() > 1)
    std::cout << (a.files.size() - failed) << " of " << a.files.size() << " parse and load\n";
  std::cout.flush();
  set_exit_code(failed == 0 ? 0 : 1);
}

}  // namespace

void add_grammar_commands(CLI::App& app) {
  auto* grammar = app.add_subcommand("grammar", "Grammar files (docs/grammar.md)");
  auto args = std::make_shared<CheckArgs>();
  auto* check = grammar->add_subcommand("check",
                                        "Parse and load grammar files (Quiver's dialect or AGM's "
                                        ".aggl): one summary line each, or the error");
  check->add_option("files", args->files, "grammar files")->required()->check(CLI::ExistingFile);
  check
      ->add_option("-I,--include-dir", args->include_dirs,
                   "where include(...) files are looked for after the including file's directory "
                   "(like AGM's "
                   "AGGLPATH); may be given several times")
      ->allow_extra_args(false)
      ->check(CLI::ExistingDirectory);
  check->add_flag("--notes", args->notes,
                  "also print the notes: what loads with a remark (undeclared types, combo "
                  "choices left out, ...)");
  check->add_option("--schema", args->schema,
                    "also check the grammar's node types and edge labels against this schema (docs/schema.md): "
                    "each one it does not declare, or an edge between types it never joins, is an error")
      ->check(CLI::ExistingFile);
  check->callback([args] { run_check(*args); });
}

}  // namespace quiver::tools
