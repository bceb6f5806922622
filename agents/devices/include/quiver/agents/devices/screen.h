#pragma once
/// @file
/// The touchscreen the patient sees, behind one interface: a real implementation that renders
/// PNG images (OpenCvScreen) and a simulated one (SimulatedScreen).
///
/// Time is the agent's clock, passed in as `now_ns`. Implementations are not thread-safe.

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "quiver/base/result.h"

namespace quiver::agents::devices {

/// What the screen shows: a title, a text and touchable options, one of which may be
/// highlighted. Strings are UTF-8.
struct ScreenContent {
  std::string title;
  std::string text;
  std::vector<std::string> options;
  int highlighted = -1;  ///< index into `options`, or -1 for none

  bool operator==(const ScreenContent&) const = default;
};

/// Most options a screen shows (every implementation checks it).
inline constexpr std::size_t kMaxScreenOptions = 8;

/// Checks `c` as every Screen::show() does.
/// @returns kInvalidArgument naming `fn` and the value when `highlighted` is neither -1 nor an
///   index into `options`, or when an option label is empty; kTooLarge when there are more than
///   kMaxScreenOptions options.
Status check_screen_content(const ScreenContent& c, const char* fn);

/// A screen that shows one content at a time.
class Screen {
 public:
  virtual ~Screen() = default;

  /// Shows `c` from `now_ns` on, replacing what was shown.
  /// @returns check_screen_content()'s errors (nothing changes then) or the device's.
  virtual Status show(const ScreenContent& c, std::int64_t now_ns) = 0;

  /// Blanks the screen; current() becomes empty.
  virtual Status clear(std::int64_t now_ns) = 0;

  /// What the screen shows now; empty before the first show() and after clear().
  virtual const std::optional<ScreenContent>& current() const = 0;

  /// The picture the screen shows now, as an encoded image file (PNG or JPEG bytes): the render
  /// of the last successful show() or clear() (a blank picture after clear()). Empty when this
  /// screen renders no pictures (SimulatedScreen: the simulator stays cheap) or has rendered
  /// none yet. Valid until the next show() or clear(). The Panel stores it in the graph.
  virtual std::span<const std::uint8_t> image() const { return {}; }
};

}  // namespace quiver::agents::devices
