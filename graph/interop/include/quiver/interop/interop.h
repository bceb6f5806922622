#pragma once
/// @file
/// What the CORTEX DSR and AGM converters share: options, reports, format detection, and the
/// conventions every converted world follows (docs/interop.md):
///
///  - lengths: both source formats store millimetres; Quiver stores metres (÷ 1000 on import,
///    × 1000 on export; LengthUnit::kMetre for the files that hold metres);
///  - rotations: both store Euler angles (rx, ry, rz) in radians with R = Rx(rx)·Ry(ry)·Rz(rz)
///    (RoboComp's RTMat, CORTEX's RT_API); Quiver stores the unit quaternion [w, x, y, z] of R;
///    an RT edge parent -> child holds X_PC: p_P = R·p_C + t;
///  - source ids are kept as node attributes (`dsr_id`: uint64, `agm_id`: string) and written
///    back by the exporters;
///  - RT edges carry no attributes in Quiver: an RT link's other attributes are kept on the
///    child node, named `rt:<name>`, and go back onto the RT link on export;
///  - a node name that Quiver cannot take is mapped: '~' becomes '-'; a name already taken
///    earlier in the file becomes `<name>_<source id>` (then `_2`, `_3`... if that is taken too);
///    empty names fall back to `<type>_<source id>`.
///
/// Nothing is half-imported: a file is read and checked whole, then applied in one transaction;
/// on any error the graph is left as it was.

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "quiver/base/result.h"

namespace quiver::interop {

/// The length unit of a file's translations. Both formats store millimetres (RoboComp's
/// convention); a few real files hold metres, which nothing in them says.
enum class LengthUnit { kMillimetre, kMetre };

/// Metres per unit (0.001 for millimetres).
inline double metres_per(LengthUnit u) { return u == LengthUnit::kMetre ? 1.0 : 0.001; }

struct ImportOptions {
  /// The unit of the file's translations.
  LengthUnit unit = LengthUnit::kMillimetre;
  /// Refuse the file when the import would warn (a link to a missing symbol that CORTEX skips, a
  /// fraction in an integer attribute, a duplicate link...), instead of importing with warnings.
  bool strict = false;
};

/// What an import added, and what it did that the file did not say exactly.
struct ImportReport {
  std::size_t nodes = 0;
  std::size_t edges = 0;     ///< symbolic edges, self-loops included
  std::size_t rt_edges = 0;
  /// Each names the file and the element, as errors do.
  std::vector<std::string> warnings;
};

struct ExportOptions {
  /// The unit to write translations in.
  LengthUnit unit = LengthUnit::kMillimetre;
};

/// A world in one of the exporters' formats.
struct ExportResult {
  std::string text;
  /// Values the target format cannot hold as they are (e.g. an int64 beyond CORTEX's int32, a
  /// vector in AGM's string attributes), each naming the node or edge and what was written.
  std::vector<std::string> warnings;
};

/// The kinds of world file the converters tell apart, for "wrong command" messages.
enum class WorldFormat {
  kUnknown,
  kQuiverJson,  ///< a Quiver world file ({"quiver_world": 1, ...})
  kDsrJson,     ///< a CORTEX DSR JSON world ({"DSRModel": ...})
  kAgmXml,      ///< an AGM XML world (root <AGMModel>)
  kOtherJson,   ///< JSON that is none of those
  kOtherXml,    ///< XML with another root element
};
const char* to_string(WorldFormat f);

/// What `text` looks like, from its first bytes and its root (a UTF-8 byte order mark and
/// leading white space are skipped). `root` receives the XML root element's name when the text
/// is XML. Never fails: malformed text is kUnknown, or the kind its first character announces.
WorldFormat detect_format(std::string_view text, std::string* root = nullptr);

/// Reads a whole file. @returns kIo naming `fn` and the path when it cannot be read.
Result<std::string> read_file(const char* fn, const std::string& path);
/// Writes a whole file. @returns kIo naming `fn` and the path on failure.
Status write_file(const char* fn, const std::string& path, std::string_view text);

}  // namespace quiver::interop
