#pragma once
/// @file
/// Laying a Picture out with Graphviz (its C library: cgraph + gvc), and Graphviz's own DOT and
/// SVG output of it. Graphviz stays out of this header.
///
/// Engines: `dot` (layered, top-down: the RT tree and the symbolic relations read as a
/// hierarchy) for pictures up to kDotMaxNodes nodes, `sfdp` (multilevel force-directed, straight
/// edges) beyond: dot's crossing minimisation and spline routing take minutes on thousands of
/// nodes, sfdp seconds (docs/viewer.md gives the figures). `neato` (stress majorisation) on
/// request.
///
/// Coordinates are Graphviz points (1/72 inch), origin at the top left of the drawing, y down.
///
/// Threading: Graphviz keeps global state, so every call here takes one process-wide lock;
/// calls from several threads are safe but run one at a time.

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "quiver/agents/view/render/picture.h"
#include "quiver/base/result.h"

namespace quiver::agents::inline view::render {

enum class Engine { kAuto, kDot, kNeato, kSfdp };
/// "auto", "dot", "neato", "sfdp".
const char* to_string(Engine e);
/// The engine named `name`; kInvalidArgument naming it and the choices otherwise.
Result<Engine> parse_engine(std::string_view name);
/// Above this many nodes kAuto picks sfdp instead of dot.
inline constexpr std::size_t kDotMaxNodes = 400;
/// `e`, or for kAuto the engine chosen for a picture of `nodes` nodes.
Engine resolve_engine(Engine e, std::size_t nodes);

/// Font sizes (points) of node labels, edge labels and the title: Graphviz sizes the nodes
/// after them, and the PNG renderer draws text to fit.
inline constexpr double kNodeFontPt = 11;
inline constexpr double kEdgeFontPt = 9;
inline constexpr double kTitleFontPt = 14;

struct Point {
  double x = 0;
  double y = 0;
};

struct NodePlace {
  Point centre;
  double width = 0;  ///< of the ellipse or box
  double height = 0;
};

struct EdgePlace {
  /// Cubic Bézier control points p0 c1 c2 p1 c1 c2 p2 ... (3k+1 points; straight edges too).
  std::vector<Point> curve;
  bool arrow = false;  ///< an arrowhead from the curve's last point to arrow_tip
  Point arrow_tip;
  bool has_label = false;
  Point label;  ///< centre of the edge's label
};

struct Layout {
  Engine engine = Engine::kDot;  ///< the one used (never kAuto)
  double width = 0;              ///< of the drawing (title excluded)
  double height = 0;
  std::vector<NodePlace> nodes;  ///< parallel to Picture::nodes
  std::vector<EdgePlace> edges;  ///< parallel to Picture::edges
};

/// How dot arranges its layers (the other engines ignore it).
struct LayoutStyle {
  enum class Direction { kTopDown, kLeftRight };
  Direction direction = Direction::kTopDown;
};

/// Lays `p` out. kInternal naming Graphviz's message when its layout fails (e.g. the engine's
/// plugin is missing).
Result<Layout> lay_out(const Picture& p, Engine engine = Engine::kAuto, LayoutStyle style = {});

/// Lays `p` out to fill a width x height picture best: with dot, top-down and left-to-right are
/// tried, and left-to-right is kept when it can be drawn 20% larger in the picture (a hub with
/// many children is one wide layer top-down); other engines lay out once.
Result<Layout> lay_out_to_fit(const Picture& p, Engine engine, double width, double height);

enum class TextFormat { kDot, kSvg };
/// Lays `p` out and returns Graphviz's own rendering of it: DOT with positions ("pos", "bb")
/// or SVG. Highlighted nodes and edges carry penwidth 3, the highlight colour and
/// class="highlight"; the title is the graph's label.
Result<std::string> graphviz_text(const Picture& p, TextFormat format,
                                  Engine engine = Engine::kAuto);

}  // namespace quiver::agents::inline view::render
