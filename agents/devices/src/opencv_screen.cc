// The touchscreen rendered with OpenCV: each show or clear written atomically as the next PNG image.
#include "quiver/agents/devices/opencv_screen.h"

#include <cstdio>
#include <stdexcept>
#include <utility>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "file_io.h"
#include "screen_renderer.h"

namespace quiver::agents::devices {

OpenCvScreen::OpenCvScreen(std::string out_dir, int width, int height)
    : out_dir_(std::move(out_dir)), width_(width), height_(height) {
  if (out_dir_.empty()) throw std::invalid_argument("OpenCvScreen(): out_dir is empty");
  if (width < 160 || width > 8192 || height < 120 || height > 8192) {
    throw std::invalid_argument("OpenCvScreen(): size " + std::to_string(width) + "x" +
                                std::to_string(height) +
                                " is outside 160x120 .. 8192x8192");
  }
}

namespace {

// Renders with `draw` and writes the PNG atomically to the next `<out_dir>/screen_NNNN.png`;
// on success `last_png` names it and `image` holds its bytes.
template <class Draw>
Status write_png(const std::string& out_dir, int& next_index, std::string& last_png,
                 std::vector<std::uint8_t>& image, const char* fn, Draw draw) {
  if (Status s = internal::ensure_directory(out_dir, fn); !s) return s;
  char name[32];
  std::snprintf(name, sizeof name, "screen_%04d.png", next_index++);
  const std::string path = out_dir + "/" + name;
  std::vector<unsigned char> png;
  try {
    cv::Mat img = draw();
    if (!cv::imencode(".png", img, png)) {
      return make_error(ErrorCode::kIo, std::string(fn) + ": OpenCV cannot encode '" + path + "'");
    }
  } catch (const cv::Exception& e) {
    return make_error(ErrorCode::kIo,
                      std::string(fn) + ": OpenCV failed on '" + path + "': " + e.what());
  }
  const std::string_view bytes(reinterpret_cast<const char*>(png.data()), png.size());
  if (Status s = internal::write_file_atomically(path, bytes, fn); !s) return s;
  last_png = path;
  image = std::move(png);
  return Status::Ok();
}

}  // namespace

Status OpenCvScreen::show(const ScreenContent& c, std::int64_t now_ns) {
  constexpr const char* kFn = "OpenCvScreen::show()";
  if (Status s = check_screen_content(c, kFn); !s) return s;
  Status s = write_png(out_dir_, next_index_, last_png_, image_, kFn,
                       [&] { return internal::render_screen(c, width_, height_); });
  if (!s) return s;
  current_ = c;
  return Status::Ok();
}

Status OpenCvScreen::clear(std::int64_t now_ns) {
  constexpr const char* kFn = "OpenCvScreen::clear()";
  Status s = write_png(out_dir_, next_index_, last_png_, image_, kFn,
                       [&] { return internal::render_blank_screen(width_, height_); });
  if (!s) return s;
  current_.reset();
  return Status::Ok();
}

}  // namespace quiver::agents::devices
