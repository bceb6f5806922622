#pragma once
/// @file
/// JSON world files: load a graph's initial content, seed a shared world, save a snapshot.
/// Format: docs/world-format.md.
///
/// Loading validates the whole file before changing anything: on any error (syntax, unknown type,
/// dangling reference, taken name, cycle) the graph is left as it was and the error names the
/// place — line:column for syntax errors, a JSON pointer such as /nodes/3/attrs/pos otherwise.
///
/// Errors are returned as values; nothing here throws on bad input. Threading: functions that
/// take a Graph run on its owner thread; the others are thread-safe.

#include <string>
#include <string_view>

#include "quiver/graph/graph.h"
#include "quiver/base/result.h"

namespace quiver::graph {

/// Statistics of a load.
struct WorldLoadInfo {
  std::size_t nodes = 0;
  std::size_t edges = 0;
  std::size_t rt_edges = 0;
};

struct WorldLoadOptions {
  /// Seed mode: nodes whose names the graph already has are left alone (not an error), and so
  /// are edges and RT edges between such nodes. For an agent that restarts and re-seeds.
  bool skip_existing = false;
};

/// Parses `text` (named `source` in errors) and adds its nodes, edges and RT edges to `g` in one
/// transaction. Names may refer to nodes `g` already has. `g`'s owner thread only.
/// @returns what was added, or kMalformed (syntax, structure, an unknown key or type, a dangling
///          name, a duplicate or taken name, an RT child with two parents) or the error of the
///          commit (e.g. kRefused from a validator, kTooLarge); on error `g` is unchanged.
Result<WorldLoadInfo> load_world(Graph& g, std::string_view text, std::string_view source = "world",
                                 const WorldLoadOptions& options = {});
/// load_world() on the contents of file `path` (errors name the path). `g`'s owner thread only.
/// @returns as load_world(), or kIo if the file cannot be opened.
Result<WorldLoadInfo> load_world_file(Graph& g, const std::string& path, const WorldLoadOptions& options = {});

/// A world file as one delta that depends on nothing but the file: its nodes, edges and RT edges
/// under dots of a replica derived from the file's content (ReplicaId{content hash, 0}),
/// numbered in file order, sequence number 1. Every agent that seeds the same file builds the
/// same bytes, so seeding is idempotent even when several agents seed at once (the replication
/// protocol sees one delta, relayed by each). The file must name only its own nodes.
struct WorldSeed {
  GraphDelta delta;
  WorldLoadInfo info;
};
/// Builds the seed of world file `text` (named `source` in errors). Thread-safe.
/// @returns the seed, or kMalformed as load_world() (a name not defined in the file included),
///          kInvalidArgument for a file that adds nothing.
Result<WorldSeed> world_seed(std::string_view text, std::string_view source = "world");
/// world_seed() on the contents of file `path`. Thread-safe.
/// @returns as world_seed(), or kIo if the file cannot be opened.
Result<WorldSeed> world_seed_file(const std::string& path);

/// The visible graph as a world file (winning values only; RT edges with their current pose).
/// `g`'s owner thread only.
/// @returns the JSON text (docs/world-format.md), nodes in id order.
std::string save_world(const Graph& g);
/// Writes save_world(g) to `path`, replacing the file. `g`'s owner thread only.
/// @returns kIo if the file cannot be opened or written.
Status save_world_file(const Graph& g, const std::string& path);

/// A Value from its JSON form (see the format document); errors name `where`. Thread-safe.
/// @returns the value, or kMalformed (not JSON, or not a value of the format).
Result<Value> value_from_json_text(std::string_view json, std::string_view where = "value");
/// The JSON form of a value (compact, one line). Thread-safe.
std::string value_to_json_text(const Value& v);

}  // namespace quiver::graph
