// A laid-out picture drawn with OpenCV: nodes filled with their type's colour, edges along their splines with
// arrowheads, each node and edge normal, highlighted or a ghost.
#include "painter.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "quiver/agents/devices/opencv_screen.h"

namespace quiver::agents::inline view::render::internal {
namespace {

constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;

cv::Scalar bgr(Rgb c) { return cv::Scalar(c.b, c.g, c.r); }

cv::Point px(cv::Point2d p) {
  return cv::Point(static_cast<int>(std::lround(p.x)), static_cast<int>(std::lround(p.y)));
}

// The OpenCV font scale whose capital letters are `cap_px` high.
double font_scale_for(double cap_px) {
  static const double cap_at_1 = [] {
    int baseline = 0;
    return static_cast<double>(cv::getTextSize("H", kFont, 1.0, 1, &baseline).height);
  }();
  return cap_px / cap_at_1;
}

// Points along a chain of cubic Béziers (3k+1 control points).
std::vector<cv::Point2d> flatten(const std::vector<Point>& curve, const View& view) {
  std::vector<cv::Point2d> out;
  if (curve.empty()) return out;
  out.push_back(view.at(curve[0]));
  for (std::size_t i = 0; i + 3 < curve.size(); i += 3) {
    const cv::Point2d p0 = view.at(curve[i]), p1 = view.at(curve[i + 1]),
                      p2 = view.at(curve[i + 2]), p3 = view.at(curve[i + 3]);
    const double len = cv::norm(p1 - p0) + cv::norm(p2 - p1) + cv::norm(p3 - p2);
    const int steps = std::clamp(static_cast<int>(len / 4), 1, 32);
    for (int s = 1; s <= steps; ++s) {
      const double t = static_cast<double>(s) / steps, u = 1 - t;
      out.push_back(u * u * u * p0 + 3 * u * u * t * p1 + 3 * u * t * t * p2 + t * t * t * p3);
    }
  }
  return out;
}

void polyline(cv::Mat& img, const std::vector<cv::Point2d>& pts, cv::Scalar colour, int thickness,
              bool dashed) {
  if (!dashed) {
    std::vector<cv::Point> ip;
    ip.reserve(pts.size());
    for (const auto& p : pts) ip.push_back(px(p));
    cv::polylines(img, ip, false, colour, thickness, cv::LINE_AA);
    return;
  }
  // Dashes of 6 px with gaps of 4, continued across the polyline's corners.
  const double dash = 6.0 * std::max(1, thickness), gap = 4.0 * std::max(1, thickness);
  double phase = 0;  // distance into the current dash+gap period
  for (std::size_t i = 1; i < pts.size(); ++i) {
    const cv::Point2d a = pts[i - 1], d = pts[i] - pts[i - 1];
    const double len = cv::norm(d);
    double done = 0;
    while (done < len) {
      const bool on = phase < dash;
      const double step = std::min(len - done, on ? dash - phase : dash + gap - phase);
      if (on)
        cv::line(img, px(a + d * (done / len)), px(a + d * ((done + step) / len)), colour,
                 thickness, cv::LINE_AA);
      done += step;
      phase = std::fmod(phase + step, dash + gap);
    }
  }
}

void arrowhead(cv::Mat& img, cv::Point2d from, cv::Point2d tip, cv::Scalar colour) {
  const cv::Point2d d = tip - from;
  const double len = cv::norm(d);
  if (len < 1e-6) return;
  const cv::Point2d n(-d.y * 0.35, d.x * 0.35);  // half the base, across the shaft
  std::vector<cv::Point> tri{px(tip), px(from + n), px(from - n)};
  cv::fillConvexPoly(img, tri, colour, cv::LINE_AA);
}

// Text centred on `centre`, at most `max_width` pixels wide.
void centred_text(cv::Mat& img, const std::string& text, cv::Point2d centre, double cap_px,
                  double max_width, Rgb colour, bool bold) {
  const std::string t = devices::to_hershey_text(text);
  if (t.empty()) return;
  double scale = font_scale_for(cap_px);
  // Hershey strokes two pixels wide smudge small letters: bold only where there is room.
  const int thickness = bold && cap_px >= 12 ? 2 : 1;
  int baseline = 0;
  cv::Size size = cv::getTextSize(t, kFont, scale, thickness, &baseline);
  if (max_width > 0 && size.width > max_width) {
    scale *= max_width / size.width;
    size = cv::getTextSize(t, kFont, scale, thickness, &baseline);
  }
  if (size.height < 4) return;  // unreadable: leave the shape alone
  cv::putText(img, t, px(centre + cv::Point2d(-size.width / 2.0, size.height / 2.0)), kFont, scale,
              bgr(colour), thickness, cv::LINE_AA);
}

void paint_edge(cv::Mat& img, const PictureEdge& e, const EdgePlace& place, Look look,
                const View& view) {
  const bool hi = look == Look::kHighlighted || look == Look::kGhost;
  const Rgb colour = hi            ? kHighlightColour
                     : e.geometric ? kGeometryColour
                                   : type_stroke_colour(e.type);
  const int thickness = std::max(1, static_cast<int>(std::lround((hi ? 3.0 : 1.0) * view.scale)));
  const std::vector<cv::Point2d> pts = flatten(place.curve, view);
  if (pts.size() >= 2)
    polyline(img, pts, bgr(colour), thickness, e.geometric || look == Look::kGhost);
  if (place.arrow && !pts.empty())
    arrowhead(img, pts.back(), view.at(place.arrow_tip), bgr(colour));
  if (place.has_label)
    centred_text(img, e.type, view.at(place.label), kEdgeFontPt * view.scale * 0.7, 0, colour,
                 look == Look::kHighlighted);
}

void paint_node(cv::Mat& img, const PictureNode& n, const NodePlace& place, Look look,
                const View& view) {
  const cv::Point2d c = view.at(place.centre);
  const double w = place.width * view.scale, h = place.height * view.scale;
  const bool hi = look == Look::kHighlighted || look == Look::kGhost;
  const Rgb outline = hi ? kHighlightColour : kInkColour;
  const int thickness = std::max(1, static_cast<int>(std::lround((hi ? 3.0 : 1.0) * view.scale)));
  if (look == Look::kGhost) {
    std::vector<cv::Point2d> pts;
    for (int a = 0; a <= 360; a += 5) {
      const double r = a * CV_PI / 180;
      pts.emplace_back(c.x + w / 2 * std::cos(r), c.y + h / 2 * std::sin(r));
    }
    if (n.geometric)
      pts = {c + cv::Point2d(-w / 2, -h / 2), c + cv::Point2d(w / 2, -h / 2),
             c + cv::Point2d(w / 2, h / 2), c + cv::Point2d(-w / 2, h / 2),
             c + cv::Point2d(-w / 2, -h / 2)};
    polyline(img, pts, bgr(outline), thickness, /*dashed=*/true);
  } else if (n.geometric) {
    const cv::Rect box(px(c - cv::Point2d(w / 2, h / 2)), px(c + cv::Point2d(w / 2, h / 2)));
    cv::rectangle(img, box, bgr(type_colour(n.type)), cv::FILLED, cv::LINE_AA);
    cv::rectangle(img, box, bgr(outline), thickness, cv::LINE_AA);
  } else {
    const cv::Size axes(std::max(1, static_cast<int>(w / 2)), std::max(1, static_cast<int>(h / 2)));
    cv::ellipse(img, px(c), axes, 0, 0, 360, bgr(type_colour(n.type)), cv::FILLED, cv::LINE_AA);
    cv::ellipse(img, px(c), axes, 0, 0, 360, bgr(outline), thickness, cv::LINE_AA);
  }
  // Two lines, as Graphviz sized them: the name, then "(type)".
  const double cap = kNodeFontPt * view.scale * 0.7;
  const double line = kNodeFontPt * view.scale * 1.2;
  const double room = w * (n.geometric ? 0.92 : 0.8);
  const Rgb ink = hi ? kHighlightColour : kInkColour;
  const bool bold = look == Look::kHighlighted;
  centred_text(img, n.name, c - cv::Point2d(0, line / 2), cap, room, ink, bold);
  centred_text(img, "(" + n.type + ")", c + cv::Point2d(0, line / 2), cap, room, ink, bold);
}

}  // namespace

void paint(cv::Mat& img, const Picture& p, const Layout& l, std::span<const Look> node_looks,
           std::span<const Look> edge_looks, const View& view) {
  // Ordinary things first, so that highlighted and ghost ones lie on top.
  for (int pass = 0; pass < 2; ++pass) {
    for (std::size_t i = 0; i < p.edges.size(); ++i) {
      const Look look = edge_looks[i];
      if (look == Look::kHidden || (look == Look::kNormal) != (pass == 0)) continue;
      paint_edge(img, p.edges[i], l.edges[i], look, view);
    }
  }
  for (int pass = 0; pass < 2; ++pass) {
    for (std::size_t i = 0; i < p.nodes.size(); ++i) {
      const Look look = node_looks[i];
      if (look == Look::kHidden || (look == Look::kNormal) != (pass == 0)) continue;
      paint_node(img, p.nodes[i], l.nodes[i], look, view);
    }
  }
}

void paint_text(cv::Mat& img, const std::string& text, cv::Point2d top_left, double px_high,
                Rgb colour, bool bold) {
  const std::string t = devices::to_hershey_text(text);
  const double scale = font_scale_for(px_high);
  cv::putText(img, t, px(top_left + cv::Point2d(0, px_high)), kFont, scale, bgr(colour),
              bold ? 2 : 1, cv::LINE_AA);
}

cv::Mat blank_image(int width, int height) {
  return cv::Mat(std::max(1, height), std::max(1, width), CV_8UC3, cv::Scalar(255, 255, 255));
}

Status write_png(const cv::Mat& img, const std::string& path, const char* fn) {
  bool ok = false;
  std::string why;
  try {
    ok = cv::imwrite(path, img);
  } catch (const cv::Exception& e) {
    why = std::string(": ") + e.what();
  }
  if (!ok)
    return make_error(ErrorCode::kIo,
                      std::string(fn) + ": could not write the PNG file '" + path + "'" + why);
  return {};
}

}  // namespace quiver::agents::inline view::render::internal
