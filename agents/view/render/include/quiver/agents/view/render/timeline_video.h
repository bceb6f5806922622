#pragma once
/// @file
/// The evolution of a recorded world as a sequence of pictures (seed 000, Fig. 6): one picture
/// per recorded change, the nodes and edges that change changed drawn bold in the highlight colour,
/// those it removed as dashed ghosts, and a caption ("t = 12.3 s  origin: planner  created X,
/// set attr on Z").
///
/// The layout is stable: every node and edge that is ever shown is laid out once, together
/// (Graphviz, layout.h), and each change draws the ones present then at those places, so nothing
/// jumps between pictures. Output: PNG pictures in a directory (0000.png, 0001.png, ...) or an MP4
/// video (OpenCV's VideoWriter, fourcc mp4v), all pictures of one size.

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "quiver/agents/view/recording/recorded_change.h"
#include "quiver/agents/view/render/layout.h"
#include "quiver/base/result.h"

namespace quiver::agents::inline view::render {

struct TimelineOptions {
  /// Leave out the geometric part (geometric_part.h) in every change.
  bool hide_geometry = false;
  /// Also draw changes that change nothing drawn. By default they are left out: changes whose
  /// changes are all hidden (with hide_geometry, those that only move things) or empty.
  bool every_change = false;
  /// Draw only changes in which a node or an edge appears or goes (attribute and pose updates
  /// are still highlighted when such a change carries them). Overrides every_change.
  bool structure_only = false;
  /// At most this many pictures, the first ones (0: no limit).
  std::size_t max_changes = 0;
  double fps = 2;  ///< of an MP4
  Engine engine = Engine::kAuto;
  /// The pictures' size: the layout is scaled down to fit (never up beyond 96 dpi).
  int max_width = 1920;
  int max_height = 1080;
};

/// What render_timeline() did.
struct TimelineInfo {
  std::size_t recorded = 0;  ///< changes in the recording
  std::size_t written = 0;   ///< pictures written
  std::size_t skipped = 0;   ///< changes left out: they changed nothing drawn (see every_change)
                             ///< or, with structure_only, nothing appeared or went
  std::size_t cut = 0;       ///< changes left out by max_changes
  int width = 0;             ///< of every picture, pixels
  int height = 0;
  std::size_t nodes = 0;  ///< laid out (every node ever shown)
  std::size_t edges = 0;
  Engine engine = Engine::kDot;
  std::vector<std::size_t> changes;    ///< the recording change of each picture
  std::vector<std::string> captions;  ///< the caption of each picture
};

/// Where render_timeline() writes: an .mp4 file, or a directory of PNG pictures (a path ending
/// in '/', an existing directory, or a path with no extension).
enum class TimelineOutput { kPngFrames, kMp4 };
/// kInvalidArgument naming the path and its extension when it is neither.
Result<TimelineOutput> timeline_output_of(const std::string& path);

/// Draws `changes` (in recorded order, the first holding the state recording began with) to
/// `out`. A directory is created if missing; PNG pictures an earlier run left there (names of
/// four or more digits, ".png") are removed first.
/// @returns kInvalidArgument for an unknown output kind or an empty recording, kIo naming the
///   path when it cannot be written (or OpenCV cannot encode MP4: no ffmpeg backend), kInternal
///   when Graphviz fails.
Result<TimelineInfo> render_timeline(std::span<const recording::RecordedChange> changes,
                                     const TimelineOptions& options, const std::string& out);

}  // namespace quiver::agents::inline view::render
