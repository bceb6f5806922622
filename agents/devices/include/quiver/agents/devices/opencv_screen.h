#pragma once
/// @file
/// A touchscreen rendered with OpenCV into PNG images, one per change.

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "quiver/agents/devices/screen.h"
#include "quiver/base/result.h"

namespace quiver::agents::devices {

/// `utf8` in the characters of OpenCV's Hershey fonts: ASCII is kept; control characters (C0,
/// DEL, C1) become spaces; U+00C0..U+00FF become their base letters ("Núñez" -> "Nunez", "ß" -> "ss"), a
/// no-break space a space, and the Spanish opening marks '¡' and '¿' are left out; every other
/// non-ASCII character (or byte that is not UTF-8) becomes one '?'.
std::string to_hershey_text(std::string_view utf8);

/// Renders each show() and clear() into `<out_dir>/screen_NNNN.png` (NNNN = 0001, 0002, ... one
/// per call that passed its checks). The image has the title at the top, the text word-wrapped
/// below it, and the options as rounded buttons with their (wrapped) labels, the highlighted one
/// in another colour; the font shrinks until everything fits. clear() writes a blank image of
/// one colour.
///
/// Drawing uses OpenCV's built-in Hershey fonts, which have only ASCII glyphs: text is drawn as
/// to_hershey_text() gives it (accented Latin letters without their accents, other non-ASCII
/// characters as '?'). current() keeps the original text. Each PNG is written to a temporary name and renamed, so a viewer never reads half an
/// image. Not thread-safe.
class OpenCvScreen final : public Screen {
 public:
  /// @param out_dir where the PNGs go; created on the first show()/clear() if missing.
  /// @pre 160 <= width <= 8192 and 120 <= height <= 8192 (else std::invalid_argument).
  explicit OpenCvScreen(std::string out_dir, int width = 800, int height = 480);

  /// @returns check_screen_content()'s errors, or kIo naming the file when the PNG cannot be
  ///   written (`out_dir` cannot be created, OpenCV fails, the rename fails).
  Status show(const ScreenContent& c, std::int64_t now_ns) override;
  /// @returns kIo naming the file when the PNG cannot be written.
  Status clear(std::int64_t now_ns) override;
  const std::optional<ScreenContent>& current() const override { return current_; }

  /// The bytes of the last PNG written (what the screen shows); empty before the first.
  std::span<const std::uint8_t> image() const override { return image_; }

  /// The path of the last PNG written; empty before the first.
  const std::string& last_png() const { return last_png_; }
  int width() const { return width_; }
  int height() const { return height_; }

 private:
  std::string out_dir_;
  int width_;
  int height_;
  int next_index_ = 1;
  std::optional<ScreenContent> current_;
  std::string last_png_;
  std::vector<std::uint8_t> image_;
};

}  // namespace quiver::agents::devices
