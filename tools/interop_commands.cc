// quiver import-dsr / import-agm: CORTEX DSR JSON and AGM XML worlds into a world file or a
// running graph. quiver export-dsr / export-agm: a world file back to them (docs/interop.md).

#include <memory>
#include <optional>
#include <string>

#include "commands.h"
#include "dds_options.h"
#include "observer.h"
#include "quiver/agents/rules/schema/schema_admission.h"
#include "quiver/agents/runtime/process/logging.h"
#include "quiver/graph/world_file.h"
#include "quiver/base/hash.h"
#include "quiver/interop/agm.h"
#include "quiver/interop/dsr.h"

namespace quiver::tools {
namespace {

enum class Format { kDsr, kAgm };

const char* command_name(bool import, Format f) {
  if (import) return f == Format::kDsr ? "quiver import-dsr" : "quiver import-agm";
  return f == Format::kDsr ? "quiver export-dsr" : "quiver export-agm";
}

interop::LengthUnit unit_of(const std::string& units) {
  return units == "m" ? interop::LengthUnit::kMetre : interop::LengthUnit::kMillimetre;
}

void add_units_option(CLI::App* cmd, std::string& units, const char* what) {
  cmd->add_option("--units", units, what)->check(CLI::IsMember({"mm", "m"}))->capture_default_str();
}

struct ImportArgs {
  Format format = Format::kDsr;
  std::string input;
  std::string out;
  std::string units = "mm";
  bool strict = false;
  DdsFlags dds;
  bool live = false;  // --domain given
  double timeout_s = 10;
};

Result<interop::ImportReport> import_into(graph::Graph& g, const ImportArgs& a) {
  interop::ImportOptions o;
  o.strict = a.strict;
  o.unit = unit_of(a.units);
  return a.format == Format::kDsr ? interop::import_dsr_file(g, a.input, o) : interop::import_agm_file(g, a.input, o);
}

int run_import(const ImportArgs& a) {
  auto log = agents::named_logger(command_name(true, a.format));
  auto report_warnings = [&](const interop::ImportReport& r) {
    for (const std::string& w : r.warnings) log->warn("{}", w);
  };
  if (!a.live) {
    graph::Graph g(graph::ReplicaId{fnv1a64(command_name(true, a.format)), 1});
    // --schema: the file is imported under it, as an agent would commit it (docs/schema.md).
    agents::DdsReplicaOptions with_schema;
    if (Status s = a.dds.apply_schema(with_schema); !s.ok()) {
      log->error("{}", s.error().message);
      return 2;
    }
    std::optional<agents::schema::SchemaAdmission> vocabulary;
    if (with_schema.schema) {
      vocabulary.emplace(with_schema.schema, nullptr);
      g.set_permission_check(vocabulary->commit_check(g.replica().agent));
    }
    auto r = import_into(g, a);
    if (!r.ok()) {
      log->error("{}", r.error().message);
      return r.error().code == ErrorCode::kIo ? 2 : 1;
    }
    report_warnings(*r);
    if (Status s = graph::save_world_file(g, a.out); !s.ok()) {
      log->error("{}", s.error().message);
      return 2;
    }
    log->info("'{}': {} nodes, {} edges, {} RT edges written to '{}'{}", a.input, r->nodes, r->edges, r->rt_edges, a.out,
              r->warnings.empty() ? "" : " (" + std::to_string(r->warnings.size()) + " warnings)");
    return 0;
  }
  // Straight into the running graph: join, import in one transaction (checked against what the
  // graph holds: a taken name refuses the whole file), wait until every live peer holds it.
  auto joined = join_as_observer(a.dds, command_name(true, a.format), a.timeout_s);
  if (!joined.ok()) {
    log->error("{}", joined.error().message);
    return 1;
  }
  agents::DdsReplica& replica = **joined;
  auto r = import_into(replica.graph(), a);
  if (!r.ok()) {
    log->error("{}", r.error().message);
    replica.replicator().leave();
    return r.error().code == ErrorCode::kIo ? 2 : 1;
  }
  report_warnings(*r);
  const std::uint64_t seq = replica.replicator().last_seq();
  const bool held = r->nodes == 0 || replica.spin_until([&] { return replica.replicator().all_peers_hold(replica.id(), seq); },
                                       static_cast<std::int64_t>(a.timeout_s * 1e9));
  replica.replicator().leave();
  if (!held) {
    log->error("'{}' was imported, but not every agent on DDS domain {} acknowledged it within {} s", a.input,
               a.dds.domain, a.timeout_s);
    return 1;
  }
  log->info("'{}': {} nodes, {} edges, {} RT edges imported into DDS domain {}", a.input, r->nodes, r->edges,
            r->rt_edges, a.dds.domain);
  return 0;
}

struct ExportArgs {
  Format format = Format::kDsr;
  std::string world;
  std::string out;
  std::string units = "mm";
};

int run_export(const ExportArgs& a) {
  auto log = agents::named_logger(command_name(false, a.format));
  graph::Graph g(graph::ReplicaId{fnv1a64(command_name(false, a.format)), 1});
  auto loaded = graph::load_world_file(g, a.world);
  if (!loaded.ok()) {
    // A CORTEX or AGM file handed over by mistake says so.
    auto text = interop::read_file("quiver export", a.world);
    const interop::WorldFormat f = text.ok() ? interop::detect_format(*text) : interop::WorldFormat::kUnknown;
    if (f == interop::WorldFormat::kDsrJson || f == interop::WorldFormat::kAgmXml)
      log->error("'{}' is {}, not a Quiver world file; import it first (quiver {})", a.world, interop::to_string(f),
                 f == interop::WorldFormat::kDsrJson ? "import-dsr" : "import-agm");
    else
      log->error("{}", loaded.error().message);
    return 2;
  }
  interop::ExportOptions o;
  o.unit = unit_of(a.units);
  auto r = a.format == Format::kDsr ? interop::export_dsr_file(g, a.out, o) : interop::export_agm_file(g, a.out, o);
  if (!r.ok()) {
    log->error("{}", r.error().message);
    return 2;
  }
  for (const std::string& w : r->warnings) log->warn("{}", w);
  log->info("'{}': {} nodes written to '{}'{}", a.world, g.node_count(), a.out,
            r->warnings.empty() ? "" : " (" + std::to_string(r->warnings.size()) + " warnings)");
  return 0;
}

void add_import(CLI::App& app, Format f) {
  auto args = std::make_shared<ImportArgs>();
  args->format = f;
  const bool dsr = f == Format::kDsr;
  auto* cmd = app.add_subcommand(dsr ? "import-dsr" : "import-agm",
                                 dsr ? "Import a RoboComp CORTEX DSR JSON world into a world file or a running graph"
                                     : "Import an AGM XML world (<AGMModel>) into a world file or a running graph");
  cmd->add_option("file", args->input, dsr ? "the CORTEX world (.json)" : "the AGM world (.xml)")
      ->required()
      ->check(CLI::ExistingFile);
  auto* out = cmd->add_option("-o,--output", args->out, "the Quiver world file to write");
  add_units_option(cmd, args->units,
                   "the unit of the file's translations: mm (RoboComp's, the default) or m (a few files hold metres)");
  cmd->add_flag("--strict", args->strict,
                "refuse the file instead of importing it with warnings (links to missing symbols, rounded "
                "integers, repeated links...)");
  args->dds.add_to(cmd);
  cmd->add_option("--timeout", args->timeout_s,
                  "--domain: give up joining, or waiting for the agents to acknowledge, after this many seconds")
      ->check(CLI::Range(0.1, 3600.0))
      ->capture_default_str();
  cmd->callback([args, cmd, out] {
    args->live = cmd->count("--domain") > 0;
    if (args->live == (out->count() > 0))
      throw CLI::ValidationError(cmd->get_name(), "give either -o WORLD.json or --domain D (one of them)");
    set_exit_code(run_import(*args));
  });
}

void add_export(CLI::App& app, Format f) {
  auto args = std::make_shared<ExportArgs>();
  args->format = f;
  const bool dsr = f == Format::kDsr;
  auto* cmd = app.add_subcommand(dsr ? "export-dsr" : "export-agm",
                                 dsr ? "Write a world file as a RoboComp CORTEX DSR JSON world"
                                     : "Write a world file as an AGM XML world (<AGMModel>)");
  cmd->add_option("world", args->world, "the Quiver world file (JSON)")->required()->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", args->out, dsr ? "the CORTEX world to write (.json)" : "the AGM world to write (.xml)")
      ->required();
  add_units_option(cmd, args->units, "the unit to write translations in: mm (RoboComp's) or m");
  cmd->callback([args] { set_exit_code(run_export(*args)); });
}

}  // namespace

void add_interop_commands(CLI::App& app) {
  add_import(app, Format::kDsr);
  add_import(app, Format::kAgm);
  add_export(app, Format::kDsr);
  add_export(app, Format::kAgm);
}

}  // namespace quiver::tools
