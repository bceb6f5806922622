#pragma once
// Drawing a laid-out picture with OpenCV (private: OpenCV stays out of the public headers).

#include <cstdint>
#include <opencv2/core.hpp>
#include <span>
#include <string>

#include "quiver/agents/view/render/layout.h"
#include "quiver/agents/view/render/picture.h"
#include "quiver/agents/view/render/type_colour.h"

namespace quiver::agents::inline view::render::internal {

/// The blank border around a drawn picture or timeline frame, in pixels.
inline constexpr int kMarginPx = 12;

/// How one node or edge is drawn.
enum class Look : std::uint8_t {
  kHidden,       ///< not drawn
  kNormal,       ///< type colours
  kHighlighted,  ///< bold, in the highlight colour
  kGhost,        ///< just removed: a dashed outline in the highlight colour, no fill
};

/// From layout points to pixels: pixel = point * scale + origin.
struct View {
  double scale = 1;
  cv::Point2d origin{0, 0};
  cv::Point2d at(const Point& p) const { return {p.x * scale + origin.x, p.y * scale + origin.y}; }
};

/// Draws edges, then nodes, of `p` at the places `l` gives, each as `node_looks[i]` /
/// `edge_looks[i]` say (spans parallel to p.nodes and p.edges).
void paint(cv::Mat& img, const Picture& p, const Layout& l, std::span<const Look> node_looks,
           std::span<const Look> edge_looks, const View& view);

/// One line of text with its top left at `top_left`, `px` pixels high (capital letters).
void paint_text(cv::Mat& img, const std::string& text, cv::Point2d top_left, double px, Rgb colour,
                bool bold = false);

/// An image of `width` x `height` pixels, white.
cv::Mat blank_image(int width, int height);

/// Writes a PNG; kIo naming `path` when it cannot.
Status write_png(const cv::Mat& img, const std::string& path, const char* fn);

}  // namespace quiver::agents::inline view::render::internal
