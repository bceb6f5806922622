#pragma once
// Drawing a ScreenContent into an image with OpenCV's Hershey fonts.

#include <opencv2/core.hpp>

#include "quiver/agents/devices/opencv_screen.h"
#include "quiver/agents/devices/screen.h"

namespace quiver::agents::devices::internal {


/// The screen showing `c`: title on top, text word-wrapped below, options as rounded buttons
/// (in one row when every label fits on one line there, else stacked), the highlighted one in
/// another colour. The font shrinks until everything fits (or reaches its smallest size).
/// @pre check_screen_content(c) passed; width, height > 0. May throw cv::Exception.
cv::Mat render_screen(const ScreenContent& c, int width, int height);

/// A blank screen: every pixel the background colour.
cv::Mat render_blank_screen(int width, int height);

}  // namespace quiver::agents::devices::internal
