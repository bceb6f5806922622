// Pictures of a world graph written as DOT, SVG or PNG, as the output's extension says.
#include "quiver/agents/view/render/render.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "painter.h"

namespace quiver::agents::inline view::render {
namespace {

using internal::kMarginPx;

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  return ext;
}

Result<cv::Mat> draw(const graph::Graph& g, const RenderOptions& o) {
  const Picture p = make_picture(g, o.picture);
  auto l = lay_out(p, o.engine);
  if (!l.ok()) return l.error();
  // The title's band does not scale with the drawing: it must stay readable.
  const double title_px = kTitleFontPt * o.pixels_per_point * 0.75;
  const int band = p.title.empty() ? 0 : static_cast<int>(std::ceil(title_px * 2));
  const int room_w = std::max(o.max_side_px - 2 * kMarginPx, 16);
  const int room_h = std::max(o.max_side_px - 2 * kMarginPx - band, 16);
  const double scale = std::min(
      {o.pixels_per_point, room_w / std::max(l->width, 1.0), room_h / std::max(l->height, 1.0)});
  const int w = std::min(static_cast<int>(std::ceil(l->width * scale)), room_w);
  const int h = std::min(static_cast<int>(std::ceil(l->height * scale)), room_h);
  cv::Mat img = internal::blank_image(w + 2 * kMarginPx, h + 2 * kMarginPx + band);
  if (!p.title.empty())
    internal::paint_text(img, p.title, {kMarginPx, kMarginPx}, title_px, kInkColour, /*bold=*/true);
  std::vector<internal::Look> nodes, edges;
  nodes.reserve(p.nodes.size());
  for (const PictureNode& n : p.nodes)
    nodes.push_back(n.highlighted ? internal::Look::kHighlighted : internal::Look::kNormal);
  edges.reserve(p.edges.size());
  for (const PictureEdge& e : p.edges)
    edges.push_back(e.highlighted ? internal::Look::kHighlighted : internal::Look::kNormal);
  internal::paint(img, p, *l, nodes, edges,
                  internal::View{scale, cv::Point2d(kMarginPx, kMarginPx + band)});
  return img;
}

Status write_text_file(const std::string& text, const std::string& path) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (out) out.write(text.data(), static_cast<std::streamsize>(text.size()));
  if (out) out.close();
  if (!out) return make_error(ErrorCode::kIo, "render_file(): could not write '" + path + "'");
  return {};
}

}  // namespace

Result<PictureFormat> picture_format_of(const std::string& path) {
  const std::string ext = lower_extension(path);
  if (ext == ".dot" || ext == ".gv") return PictureFormat::kDot;
  if (ext == ".svg") return PictureFormat::kSvg;
  if (ext == ".png") return PictureFormat::kPng;
  return make_error(
      ErrorCode::kInvalidArgument,
      "render_file(): cannot tell the picture format of '" + path + "' from " +
          (ext.empty() ? std::string("its missing extension") : "its extension '" + ext + "'") +
          " (use .png, .svg or .dot)");
}

Result<std::string> render_text(const graph::Graph& g, const RenderOptions& options,
                                TextFormat format) {
  return graphviz_text(make_picture(g, options.picture), format, options.engine);
}

Result<std::vector<unsigned char>> render_png(const graph::Graph& g, const RenderOptions& options) {
  auto img = draw(g, options);
  if (!img.ok()) return img.error();
  std::vector<unsigned char> bytes;
  if (!cv::imencode(".png", *img, bytes))
    return make_error(ErrorCode::kInternal, "render_png(): OpenCV could not encode a PNG");
  return bytes;
}

Status render_file(const graph::Graph& g, const RenderOptions& options,
                   const std::string& out_path) {
  auto format = picture_format_of(out_path);
  if (!format.ok()) return format.error();
  if (*format == PictureFormat::kPng) {
    auto img = draw(g, options);
    if (!img.ok()) return img.error();
    return internal::write_png(*img, out_path, "render_file()");
  }
  auto text =
      render_text(g, options, *format == PictureFormat::kDot ? TextFormat::kDot : TextFormat::kSvg);
  if (!text.ok()) return text.error();
  return write_text_file(*text, out_path);
}

}  // namespace quiver::agents::inline view::render
