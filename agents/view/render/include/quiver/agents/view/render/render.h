#pragma once
/// @file
/// Pictures of a world graph: `render_file()` writes a DOT file (Graphviz's, with positions), an
/// SVG (Graphviz's) or a PNG (laid out by Graphviz, drawn with OpenCV: nodes filled with their
/// type's colour, edges along Graphviz's splines with arrowheads, highlighted things bold in the
/// highlight colour, the title above), chosen by the output's extension.

#include <string>
#include <vector>

#include "quiver/agents/view/render/layout.h"
#include "quiver/agents/view/render/picture.h"
#include "quiver/graph/graph.h"
#include "quiver/base/result.h"

namespace quiver::agents::inline view::render {

struct RenderOptions {
  PictureOptions picture;  ///< what is shown (geometry, highlights, title)
  Engine engine = Engine::kAuto;
  /// PNG only: pixels per layout point (96 dpi: 4/3), lowered so that the longer side of the
  /// picture (title included) stays within max_side_px.
  double pixels_per_point = 96.0 / 72.0;
  int max_side_px = 4096;
};

enum class PictureFormat { kDot, kSvg, kPng };
/// The format of `path` by its extension (.dot, .gv, .svg, .png; any case); kInvalidArgument
/// naming the path and its extension otherwise.
Result<PictureFormat> picture_format_of(const std::string& path);

/// Writes the picture of `g` to `out_path` in the format its extension names.
/// @returns kInvalidArgument for an unknown extension, kIo naming the path when it cannot be
///          written, kInternal when Graphviz fails (its message included).
Status render_file(const graph::Graph& g, const RenderOptions& options,
                   const std::string& out_path);

/// The DOT or SVG text of the picture of `g` (what render_file() writes for .dot and .svg).
Result<std::string> render_text(const graph::Graph& g, const RenderOptions& options,
                                TextFormat format);

/// The PNG bytes of the picture of `g` (what render_file() writes for .png).
Result<std::vector<unsigned char>> render_png(const graph::Graph& g, const RenderOptions& options);

}  // namespace quiver::agents::inline view::render
