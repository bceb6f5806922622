// One colour per node or edge type, the same everywhere: the type's name hashed onto a fixed palette.
#include "quiver/agents/view/render/type_colour.h"

#include <array>
#include <cstdio>

#include "quiver/base/hash.h"

namespace quiver::agents::inline view::render {
namespace {

// ColorBrewer's Set3, Pastel1 and Pastel2 without their greys, their duplicates and the salmon
// that reads as the highlight colour.
constexpr std::array<Rgb, 20> kPalette{{
    {0x8d, 0xd3, 0xc7}, {0xff, 0xff, 0xb3}, {0xbe, 0xba, 0xda}, {0x80, 0xb1, 0xd3},
    {0xfd, 0xb4, 0x62}, {0xb3, 0xde, 0x69}, {0xfc, 0xcd, 0xe5}, {0xbc, 0x80, 0xbd},
    {0xcc, 0xeb, 0xc5}, {0xff, 0xed, 0x6f}, {0xfb, 0xb4, 0xae}, {0xb3, 0xcd, 0xe3},
    {0xde, 0xcb, 0xe4}, {0xfe, 0xd9, 0xa6}, {0xe5, 0xd8, 0xbd}, {0xb3, 0xe2, 0xcd},
    {0xfd, 0xcd, 0xac}, {0xf4, 0xca, 0xe4}, {0xe6, 0xf5, 0xc9}, {0xf1, 0xe2, 0xcc},
}};

}  // namespace

Rgb type_colour(std::string_view type) { return kPalette[fnv1a64(type) % kPalette.size()]; }

Rgb type_stroke_colour(std::string_view type) {
  const Rgb c = type_colour(type);
  auto dark = [](std::uint8_t v) { return static_cast<std::uint8_t>(v * 45 / 100); };
  return Rgb{dark(c.r), dark(c.g), dark(c.b)};
}

std::string css_hex(Rgb c) {
  char buf[8];
  std::snprintf(buf, sizeof buf, "#%02x%02x%02x", c.r, c.g, c.b);
  return buf;
}

}  // namespace quiver::agents::inline view::render
