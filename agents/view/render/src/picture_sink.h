#pragma once
// Where the timeline's pictures go: numbered PNG files in a directory, or an MP4 video.

#include <memory>
#include <opencv2/core.hpp>
#include <string>

#include "quiver/agents/view/render/timeline_video.h"
#include "quiver/base/result.h"

namespace quiver::agents::inline view::render::internal {

class PictureSink {
 public:
  virtual ~PictureSink() = default;
  /// Appends one picture (all of one size).
  virtual Status add(const cv::Mat& img) = 0;
  /// Finishes the file (the video's index); nothing more may be added.
  virtual Status close() = 0;
};

/// A sink for `kind` at `path`, for pictures of width x height. kIo naming the path when it
/// cannot be opened.
Result<std::unique_ptr<PictureSink>> open_picture_sink(TimelineOutput kind, const std::string& path,
                                                   int width, int height, double fps,
                                                   std::size_t expected_pictures);

}  // namespace quiver::agents::inline view::render::internal
