#pragma once
/// @file
/// One colour per node or edge type, the same in every picture, video and page: the type's name
/// is hashed (FNV-1a 64) onto a fixed palette of 20 light colours on which black text reads.
/// The web viewer computes colours with these functions on the server, so they agree
/// everywhere. Changing the palette or the hash changes every picture: don't, lightly.

#include <cstdint>
#include <string>
#include <string_view>

namespace quiver::agents::inline view::render {

struct Rgb {
  std::uint8_t r = 0;
  std::uint8_t g = 0;
  std::uint8_t b = 0;
  friend bool operator==(const Rgb&, const Rgb&) = default;
};

/// The fill colour of nodes of type `type` (one of the palette's light colours).
Rgb type_colour(std::string_view type);
/// The stroke colour of edges of type `type`: type_colour() darkened so that a line reads on
/// white. Geometry (RT) edges are drawn in kGeometryColour instead.
Rgb type_stroke_colour(std::string_view type);
/// "#rrggbb" (lowercase), for SVG, DOT and CSS.
std::string css_hex(Rgb c);

/// Highlighted (changed, asked-for) nodes and edges: outline and lines in this colour, bold.
inline constexpr Rgb kHighlightColour{214, 39, 40};
/// RT edges: dashed, in this grey.
inline constexpr Rgb kGeometryColour{150, 150, 150};
/// Text and ordinary outlines.
inline constexpr Rgb kInkColour{34, 34, 34};

}  // namespace quiver::agents::inline view::render
