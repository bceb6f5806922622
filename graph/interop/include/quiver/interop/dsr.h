#pragma once
/// @file
/// RoboComp CORTEX DSR JSON worlds (docs/interop.md, "CORTEX DSR JSON").
///
/// Every layout in use is read:
///  - the current one: {"DSRModel": {"symbols": {"<id>": {"attribute": {name: {"type": CODE,
///    "value": V}}, "id", "links": [{"src", "dst", "label", "linkAttribute": {...}}], "name",
///    "type"}}}};
///  - the older ones: "symbol" instead of "symbols", symbols as an array, attributes as an array
///    of {"key", "value"[, "type"]}, links in a top-level "link" array, type codes and values as
///    strings, values without a type code (typed by their content), a UTF-8 byte order mark;
///  - RT links from `rt_translation` + `rt_rotation_euler_xyz` (the newest sample of a history
///    pack, by `rt_timestamps`), `translation` + `rotation_euler_xyz`, `trans` + `rot`, or the
///    scalars `tx ty tz rx ry rz`.
/// Type codes (CORTEX's ValType): 0 string, 1 int32, 2 float, 3 float_vec, 4 bool, 5 bytes,
/// 6 uint32, 7 uint64, 8 double, 9 uint64_vec, 10 vec2f, 11 vec3f, 12 vec4f, 13 vec6f.
///
/// Errors name the file and the element by JSON pointer
/// ("dsr.json:/DSRModel/symbols/12/attribute/pos: type code 3 expects an array of numbers");
/// syntax errors by line and column.

#include <string>
#include <string_view>

#include "quiver/graph/graph.h"
#include "quiver/interop/interop.h"
#include "quiver/base/result.h"

namespace quiver::interop {

/// Parses a CORTEX DSR JSON world (`source` names it in messages) and adds it to `g` in one
/// transaction. Each symbol becomes a node named by its "name" (docs/interop.md for the
/// mapping) with its CORTEX id in the attribute `dsr_id` (uint64).
/// @returns kMalformed for a file that is not a DSR world or breaks its rules (naming the
/// element; a Quiver world file or an AGM XML world is named as such), kAlreadyExists when a
/// name is taken in `g`, kRefused under options.strict when the import would warn; `g` is
/// unchanged on any error.
Result<ImportReport> import_dsr(graph::Graph& g, std::string_view text, std::string_view source = "dsr.json",
                                const ImportOptions& options = {});
/// Reads and imports a file. @returns kIo when it cannot be read, else as import_dsr().
Result<ImportReport> import_dsr_file(graph::Graph& g, const std::string& path, const ImportOptions& options = {});

/// The visible graph as a CORTEX DSR JSON world in the current layout: node ids from `dsr_id`
/// (fresh ids above the largest for nodes without one, or with a duplicate), attributes with
/// their type codes, RT edges as links with `rt_translation` (mm) and `rt_rotation_euler_xyz`
/// (rad) plus the child's `rt:` attributes. Nodes without `dsr_id` also get CORTEX's own
/// bookkeeping attributes `level` (depth in the RT tree) and `parent` (their RT parent's id)
/// unless they have them.
ExportResult export_dsr(const graph::Graph& g, const ExportOptions& options = {});
/// export_dsr() into a file. @returns kIo when it cannot be written.
Result<ExportResult> export_dsr_file(const graph::Graph& g, const std::string& path,
                                     const ExportOptions& options = {});

}  // namespace quiver::interop
