#pragma once
/// @file
/// A world file of any kind the project reads, told apart by its content (detect_format()):
/// Quiver's JSON (graph/world_file.h), CORTEX DSR JSON or AGM XML (docs/interop.md).

#include <string>
#include <string_view>

#include "quiver/base/result.h"
#include "quiver/graph/graph.h"

namespace quiver::interop {

/// Loads `text` into `g` in one transaction, with the loader its kind calls for (millimetres for
/// the converters' translations; warnings dropped). Owner thread of `g`.
/// @returns kMalformed naming `source` for text of another kind; otherwise the loader's error
///          (a refused commit included: nothing is loaded then).
Status load_any_world(graph::Graph& g, std::string_view text, const std::string& source);
/// As load_any_world(), from the file at `path` (errors name it; kIo if it cannot be read).
Status load_any_world_file(graph::Graph& g, const std::string& path);

}  // namespace quiver::interop
