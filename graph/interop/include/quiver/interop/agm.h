#pragma once
/// @file
/// AGM XML worlds, <AGMModel> (docs/interop.md, "AGM XML").
///
///   <AGMModel>
///     <symbol id="5" type="room" x="-330" y="800">
///       <attribute key="imName" value="kitchen"/>
///     </symbol>
///     <link src="1" dst="5" label="in"/>
///     <link src="0" dst="1" label="RT">
///       <linkAttribute key="tx" value="1200"/> ... ty tz (mm) rx ry rz (rad)
///     </link>
///   </AGMModel>
///
/// Each symbol becomes a node named by its `name` XML attribute, else its `imName` attribute,
/// else `<type>_<id>` (room_5); the id is kept in the attribute `agm_id` (a string, as written),
/// the editor position x, y in `agm_x`, `agm_y`. Attribute values are strings in AGM; they are
/// typed by their content: an integer is an int64, a decimal number a double, true/false a bool,
/// anything else a string. Links labelled RT are RT edges (tx ty tz rx ry rz, missing ones 0, as
/// AGM reads them; their other attributes go to the child as `rt:<key>`); any other link is an
/// edge, a link from a symbol to itself a unary predicate.
///
/// Errors name the file, the line and the element
/// ("world.xml:42: <link src=\"7\" dst=\"99\" label=\"in\">: no symbol with id 99").

#include <string>
#include <string_view>

#include "quiver/graph/graph.h"
#include "quiver/interop/interop.h"
#include "quiver/base/result.h"

namespace quiver::interop {

/// Parses an AGM XML world and adds it to `g` in one transaction.
/// @returns kMalformed for a file that is not an AGM world or breaks its rules (a CORTEX JSON
/// world or a Quiver world file is named as such), kAlreadyExists when a name is taken in `g`,
/// kRefused under options.strict when the import would warn; `g` is unchanged on any error.
Result<ImportReport> import_agm(graph::Graph& g, std::string_view text, std::string_view source = "world.xml",
                                const ImportOptions& options = {});
/// Reads and imports a file. @returns kIo when it cannot be read, else as import_agm().
Result<ImportReport> import_agm_file(graph::Graph& g, const std::string& path, const ImportOptions& options = {});

/// The visible graph as an AGM XML world: symbol ids from `agm_id` (fresh numbers above the
/// largest for nodes without one, or with a duplicate), x/y from `agm_x`/`agm_y`, every other
/// attribute as text (numbers in their shortest exact form; a double always with a '.' or an
/// exponent so that it reads back as a double), RT edges as RT links with tx ty tz (mm) and rx
/// ry rz (rad) plus the child's `rt:` attributes; a `name` XML attribute on symbols whose node
/// name is not what imName or <type>_<id> would give.
ExportResult export_agm(const graph::Graph& g, const ExportOptions& options = {});
/// export_agm() into a file. @returns kIo when it cannot be written.
Result<ExportResult> export_agm_file(const graph::Graph& g, const std::string& path,
                                     const ExportOptions& options = {});

}  // namespace quiver::interop
