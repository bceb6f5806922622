// quiver schema infer: a starting schema from worlds (Quiver JSON, CORTEX DSR JSON, AGM XML) and
// grammars; quiver schema check: worlds and grammars against a schema (docs/schema.md).

#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "commands.h"
#include "grammar_schema.h"
#include "quiver/agents/rules/mission/mission.h"
#include "quiver/agents/rules/schema/infer.h"
#include "quiver/agents/rules/schema/schema_admission.h"
#include "quiver/base/hash.h"
#include "quiver/interop/any_world.h"
#include "quiver/interop/interop.h"

namespace quiver::tools {
namespace {

namespace schema = agents::schema;

struct SchemaArgs {
  std::vector<std::string> files;
  std::vector<std::string> missions;  ///< --mission: AGM targets of either form (.aggt or XML)
  std::string schema, out;
  std::vector<std::string> include_dirs;
};

bool ends_with(const std::string& path, const std::string& ext) {
  return path.size() > ext.size() && path.compare(path.size() - ext.size(), ext.size(), ext) == 0;
}
bool is_grammar(const std::string& path) { return ends_with(path, ".aggl"); }
bool is_mission(const std::string& path) { return ends_with(path, ".aggt"); }

// A world of any kind the importers read is loaded in one transaction, so a schema check
// installed on the graph sees it whole.
using interop::load_any_world_file;

void run_infer(const SchemaArgs& a) {
  schema::Schema s;
  for (const std::string& file : a.files) {
    if (is_grammar(file)) {
      auto g = agents::load_grammar_file(file, a.include_dirs);
      if (!g.ok()) {
        std::cerr << file << ": error: " << g.error().message << "\n";
        return set_exit_code(1);
      }
      infer_from_grammar(*g, s);
      continue;
    }
    graph::Graph g(graph::ReplicaId{fnv1a64("quiver-schema"), 1});
    if (Status st = load_any_world_file(g, file); !st.ok()) {
      std::cerr << file << ": error: " << st.error().message << "\n";
      return set_exit_code(1);
    }
    schema::infer_from_graph(g, s);
  }
  const std::string text = s.to_json();
  if (a.out.empty()) {
    std::cout << text;
  } else if (Status st = interop::write_file("schema infer", a.out, text); !st.ok()) {
    std::cerr << st.error().message << "\n";
    return set_exit_code(1);
  } else {
    std::cout << a.out << ": " << s.node_types().size() << " node types, " << s.edge_types().size()
              << " edge types, " << s.attributes().size() << " attributes\n";
  }
  set_exit_code(0);
}

void run_check(const SchemaArgs& a) {
  auto loaded = schema::Schema::load(a.schema);
  if (!loaded.ok()) {
    std::cout << "error: " << loaded.error().message << "\n";
    return set_exit_code(1);
  }
  if (a.files.empty() && a.missions.empty()) {
    std::cout << "error: schema check: no file to check (worlds, grammars, missions; --mission FILE)\n";
    return set_exit_code(1);
  }
  auto s = std::make_shared<const schema::Schema>(std::move(*loaded));
  int failed = 0;
  std::vector<std::pair<std::string, bool>> files;  // (path, read as a mission)
  for (const std::string& file : a.files) files.emplace_back(file, is_mission(file));
  for (const std::string& file : a.missions) files.emplace_back(file, true);
  for (const auto& [file, mission] : files) {
    std::vector<std::string> errors;
    if (mission) {
      auto m = agents::load_mission_file(file);
      if (!m.ok()) errors.push_back(m.error().message);
      else pattern_schema_errors(m->pattern, *s, "mission", errors);
    } else if (is_grammar(file)) {
      auto g = agents::load_grammar_file(file, a.include_dirs);
      if (!g.ok()) errors.push_back(g.error().message);
      else errors = grammar_schema_errors(*g, *s);
    } else {
      graph::Graph g(graph::ReplicaId{fnv1a64("quiver-schema"), 1});
      schema::SchemaAdmission adm(s, nullptr);
      g.set_permission_check(adm.commit_check(g.replica().agent));
      if (Status st = load_any_world_file(g, file); !st.ok()) errors.push_back(st.error().message);
    }
    if (errors.empty()) {
      std::cout << file << ": ok\n";
      continue;
    }
    ++failed;
    for (const std::string& e : errors) std::cout << file << ": error: " << e << "\n";
  }
  std::cout.flush();
  set_exit_code(failed == 0 ? 0 : 1);
}

}  // namespace

void add_schema_commands(CLI::App& app) {
  auto* cmd = app.add_subcommand("schema", "The shared vocabulary: node types, edge types, attributes (docs/schema.md)");
  auto args = std::make_shared<SchemaArgs>();
  auto* infer = cmd->add_subcommand(
      "infer", "Write a starting schema from worlds (Quiver JSON, CORTEX DSR JSON, AGM XML) and grammars (.aggl)");
  infer->add_option("files", args->files, "worlds and grammars")->required()->check(CLI::ExistingFile);
  infer->add_option("-o,--out", args->out, "write the schema here (default: standard output)");
  infer->add_option("-I,--include-dir", args->include_dirs, "where grammars' include(...) files are looked for")
      ->check(CLI::ExistingDirectory);
  infer->callback([args] { run_infer(*args); });
  auto* check = cmd->add_subcommand("check", "Check worlds, grammars (.aggl) and missions (.aggt) against a schema: ok, "
                                             "or what it refuses");
  check->add_option("schema", args->schema, "the schema file")->required()->check(CLI::ExistingFile);
  check->add_option("files", args->files, "worlds, grammars and missions (.aggt)")->check(CLI::ExistingFile);
  check->add_option("-m,--mission", args->missions,
                    "a mission of either form (.aggt, or AGM XML: an <AGMModel> pattern, which a world's file "
                    "name would not tell apart)")
      ->check(CLI::ExistingFile);
  check->add_option("-I,--include-dir", args->include_dirs, "where grammars' include(...) files are looked for")
      ->check(CLI::ExistingDirectory);
  check->callback([args] { run_check(*args); });
}

}  // namespace quiver::tools
