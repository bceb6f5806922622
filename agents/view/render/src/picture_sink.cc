// Where the timeline's pictures go: numbered PNG files in a directory, or an MP4 video.
#include "picture_sink.h"

#include <filesystem>
#include <opencv2/videoio.hpp>
#include <regex>
#include <system_error>

#include "painter.h"

namespace quiver::agents::inline view::render::internal {
namespace {

namespace fs = std::filesystem;

class PngDirectory final : public PictureSink {
 public:
  PngDirectory(fs::path dir, int digits) : dir_(std::move(dir)), digits_(digits) {}
  Status add(const cv::Mat& img) override {
    std::string name = std::to_string(next_++);
    if (static_cast<int>(name.size()) < digits_) name.insert(0, digits_ - name.size(), '0');
    return write_png(img, (dir_ / (name + ".png")).string(), "render_timeline()");
  }
  Status close() override { return {}; }

 private:
  fs::path dir_;
  int digits_;
  std::size_t next_ = 0;
};

class Mp4File final : public PictureSink {
 public:
  explicit Mp4File(std::string path) : path_(std::move(path)) {}
  Status open(int width, int height, double fps) {
    try {
      writer_.open(path_, cv::VideoWriter::fourcc('m', 'p', '4', 'v'), fps, cv::Size(width, height),
                   true);
    } catch (const cv::Exception& e) {
      return make_error(ErrorCode::kIo, "render_timeline(): OpenCV could not open '" + path_ +
                                            "' for an MP4 video: " + e.what());
    }
    if (!writer_.isOpened())
      return make_error(ErrorCode::kIo, "render_timeline(): OpenCV could not open '" + path_ +
                                            "' for an MP4 video (fourcc mp4v: is the folder "
                                            "writable, and OpenCV's ffmpeg backend installed?)");
    return {};
  }
  Status add(const cv::Mat& img) override {
    writer_.write(img);
    return {};
  }
  Status close() override {
    writer_.release();
    std::error_code ec;
    if (!fs::exists(path_, ec) || fs::file_size(path_, ec) == 0)
      return make_error(ErrorCode::kIo,
                        "render_timeline(): OpenCV wrote nothing to '" + path_ + "'");
    return {};
  }

 private:
  std::string path_;
  cv::VideoWriter writer_;
};

}  // namespace

Result<std::unique_ptr<PictureSink>> open_picture_sink(TimelineOutput kind, const std::string& path,
                                                   int width, int height, double fps,
                                                   std::size_t expected_pictures) {
  if (kind == TimelineOutput::kMp4) {
    auto sink = std::make_unique<Mp4File>(path);
    if (Status s = sink->open(width, height, fps); !s.ok()) return s.error();
    return std::unique_ptr<PictureSink>(std::move(sink));
  }
  const fs::path dir(path);
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir))
    return make_error(ErrorCode::kIo, "render_timeline(): could not create the directory '" + path +
                                          "'" + (ec ? ": " + ec.message() : std::string()));
  // Frames of an earlier, longer run would read as part of this one.
  static const std::regex kFrameName("[0-9]{4,}\\.png");
  for (const auto& entry : fs::directory_iterator(dir, ec))
    if (entry.is_regular_file() && std::regex_match(entry.path().filename().string(), kFrameName))
      fs::remove(entry.path(), ec);
  int digits = 4;
  for (std::size_t n = expected_pictures; n >= 10000; n /= 10) ++digits;
  return std::unique_ptr<PictureSink>(std::make_unique<PngDirectory>(dir, digits));
}

}  // namespace quiver::agents::inline view::render::internal
