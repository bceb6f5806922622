// quiver render: a picture (PNG, SVG, DOT) of a world file, a recording's state or a live
// domain. quiver timeline: a recording's evolution as PNG pictures or an MP4.

#include <cctype>
#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "commands.h"
#include "dds_options.h"
#include "observer.h"
#include "quiver/agents/view/recording/record_file.h"
#include "quiver/agents/view/render/render.h"
#include "quiver/agents/view/render/render_replay.h"
#include "quiver/agents/view/render/timeline_video.h"
#include "quiver/agents/runtime/process/logging.h"
#include "quiver/graph/world_file.h"
#include "quiver/base/hash.h"

namespace quiver::tools {
namespace {

namespace render = agents::render;
namespace recording = agents::recording;

std::string lower_extension(const std::string& path) {
  const auto dot = path.find_last_of("./");
  if (dot == std::string::npos || path[dot] != '.') return "";
  std::string ext = path.substr(dot);
  for (char& ch : ext) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return ext;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Reads a recording and says what was left out of it (a change cut short at the end).
Result<recording::Recording> read_recording_noting(const std::string& path, const char* command) {
  auto rec = recording::read_recording(path);
  if (rec.ok() && !rec->note.empty())
    agents::named_logger(command)->warn("'{}': {}", path, rec->note);
  return rec;
}

// ---------------------------------------------------------------------------- quiver render

struct RenderArgs {
  std::string input;
  std::string out;
  bool hide_geometry = false;
  std::string engine = "auto";
  std::vector<std::string> highlight;
  std::optional<std::uint64_t> at;
  std::string title;
  DdsFlags dds;
  bool live = false;  // --domain given
  double timeout_s = 10;
};

// The graph a render reads: from a world file, a recording, or a live domain (kept alive with
// its replica).
struct Source {
  std::unique_ptr<graph::Graph> owned;
  std::unique_ptr<agents::DdsReplica> replica;
  std::vector<recording::RecordedChange> changes;
  std::unique_ptr<render::Replay> replay;
  const graph::Graph* graph = nullptr;
  std::string name;  // for messages
};

Result<Source> open_source(const RenderArgs& a) {
  Source s;
  if (a.live) {
    s.name = "DDS domain " + std::to_string(a.dds.domain);
    auto joined = join_as_observer(a.dds, "quiver-render", a.timeout_s);
    if (!joined.ok()) return joined.error();
    s.replica = std::move(joined.value());
    s.graph = &s.replica->graph();
    return s;
  }
  s.name = "'" + a.input + "'";
  const std::string ext = lower_extension(a.input);
  if (ext == ".qrec") {
    auto rec = read_recording_noting(a.input, "quiver render");
    if (!rec.ok()) return rec.error();
    s.changes = std::move(rec->changes);
    if (s.changes.empty())
      return make_error(ErrorCode::kInvalidArgument,
                        "the recording '" + a.input + "' holds no frames");
    const std::uint64_t last = s.changes.size() - 1;
    if (a.at && *a.at > last)
      return make_error(ErrorCode::kInvalidArgument,
                        "--at " + std::to_string(*a.at) + ": the recording '" + a.input +
                            "' holds frames 0.." + std::to_string(last));
    s.replay = std::make_unique<render::Replay>(s.changes);
    s.replay->run_through(a.at.value_or(last));
    s.graph = &s.replay->graph();
    return s;
  }
  if (a.at)
    return make_error(ErrorCode::kInvalidArgument,
                      "--at needs a recording (.qrec), and '" + a.input + "' is not one");
  if (ext != ".json")
    return make_error(ErrorCode::kInvalidArgument,
                      "cannot tell whether '" + a.input +
                          "' is a world file (.json) or a recording (.qrec) from its extension");
  s.owned = std::make_unique<graph::Graph>(graph::ReplicaId{fnv1a64("quiver-render"), 1});
  auto loaded = graph::load_world_file(*s.owned, a.input);
  if (!loaded.ok()) return loaded.error();
  s.graph = s.owned.get();
  return s;
}

int run_render(const RenderArgs& a) {
  auto log = agents::named_logger("quiver render");
  const auto t0 = std::chrono::steady_clock::now();
  render::RenderOptions o;
  o.picture.hide_geometry = a.hide_geometry;
  o.picture.title = a.title;
  auto engine = render::parse_engine(a.engine);
  if (!engine.ok()) {
    log->error("{}", engine.error().message);
    return 2;
  }
  o.engine = *engine;
  // Before reading the input: a wrong extension is known at once.
  if (auto format = render::picture_format_of(a.out); !format.ok()) {
    log->error("{}", format.error().message);
    return 2;
  }
  auto source = open_source(a);
  if (!source.ok()) {
    log->error("{}", source.error().message);
    return 1;
  }
  const graph::Graph& g = *source->graph;
  for (const std::string& name : a.highlight) {
    auto id = g.find_node(name);
    if (!id) {
      log->error("--highlight: no node is named '{}' in {}", name, source->name);
      return 1;
    }
    o.picture.highlight_nodes.insert(*id);
  }
  const render::Picture picture = render::make_picture(g, o.picture);
  if (Status s = render::render_file(g, o, a.out); !s.ok()) {
    log->error("{}", s.error().message);
    return 1;
  }
  log->info("wrote {}: {} nodes, {} edges, {} layout, {:.2f} s", a.out, picture.nodes.size(),
            picture.edges.size(),
            render::to_string(render::resolve_engine(o.engine, picture.nodes.size())),
            seconds_since(t0));
  return 0;
}

// ---------------------------------------------------------------------------- quiver timeline

struct TimelineArgs {
  std::string input;
  std::string out;
  render::TimelineOptions options;
  std::string engine = "auto";
};

int run_timeline(TimelineArgs a) {
  auto log = agents::named_logger("quiver timeline");
  const auto t0 = std::chrono::steady_clock::now();
  auto engine = render::parse_engine(a.engine);
  if (!engine.ok()) {
    log->error("{}", engine.error().message);
    return 2;
  }
  a.options.engine = *engine;
  if (auto kind = render::timeline_output_of(a.out); !kind.ok()) {
    log->error("{}", kind.error().message);
    return 2;
  }
  auto rec = read_recording_noting(a.input, "quiver timeline");
  if (!rec.ok()) {
    log->error("{}", rec.error().message);
    return 1;
  }
  if (rec->changes.empty()) {
    log->error("the recording '{}' holds no frames", a.input);
    return 1;
  }
  auto info = render::render_timeline(rec->changes, a.options, a.out);
  if (!info.ok()) {
    log->error("{}", info.error().message);
    return 1;
  }
  log->info(
      "wrote {}: {} pictures of {}x{} from {} frames ({} left out, {} over --max-frames); "
      "{} nodes, {} edges, {} layout, {:.2f} s",
      a.out, info->written, info->width, info->height, info->recorded, info->skipped, info->cut,
      info->nodes, info->edges, render::to_string(info->engine), seconds_since(t0));
  return 0;
}

}  // namespace

void add_render_commands(CLI::App& app) {
  auto ra = std::make_shared<RenderArgs>();
  auto* r = app.add_subcommand("render",
                               "Draw a world file, a recording's state or a live domain's graph "
                               "(PNG, SVG or DOT; Graphviz layout)");
  auto* input = r->add_option("input", ra->input,
                              "a world file (.json) or a recording (.qrec: its final state)");
  r->add_option("-o,--out", ra->out,
                "the picture: .png (drawn with OpenCV), .svg or .dot (Graphviz's)")
      ->required();
  r->add_flag(
      "--hide-geometry", ra->hide_geometry,
      "leave out RT edges and the nodes that take part in no other edge (as AGM's viewer does)");
  r->add_option("--engine", ra->engine,
                "layout: auto (dot up to 400 nodes, sfdp beyond), dot, neato or sfdp")
      ->capture_default_str();
  r->add_option("--highlight", ra->highlight,
                "draw these nodes bold in the highlight colour (names)");
  r->add_option("--at", ra->at,
                "a recording: the state after this frame (0 = the first) instead of the last")
      ->check(CLI::Range(std::uint64_t{0}, std::uint64_t{1} << 40));
  r->add_option("--title", ra->title, "a line above the picture");
  ra->dds.add_to(r);
  r->add_option("--timeout", ra->timeout_s, "--domain: give up joining after this many seconds")
      ->check(CLI::Range(0.1, 3600.0))
      ->capture_default_str();
  r->callback([ra, r, input] {
    ra->live = r->count("--domain") > 0;
    if (ra->live == (input->count() > 0))
      throw CLI::ValidationError("quiver render",
                                 "give either an input file or --domain D (one of them)");
    set_exit_code(run_render(*ra));
  });

  auto ta = std::make_shared<TimelineArgs>();
  auto* t = app.add_subcommand(
      "timeline",
      "Draw a recording's evolution, changes highlighted, as PNG frames in a directory or an MP4");
  t->add_option("recording", ta->input, "the recording (.qrec)")->required();
  t->add_option("-o,--out", ta->out,
                "an .mp4 file, or a directory (DIR/ : 0000.png, 0001.png, ...)")
      ->required();
  t->add_flag("--hide-geometry", ta->options.hide_geometry,
              "leave out RT edges and the nodes that take part in no other edge, and the frames "
              "that only change them");
  t->add_flag("--every-frame", ta->options.every_change,
              "also draw frames that change nothing drawn");
  t->add_flag(
      "--structure-only", ta->options.structure_only,
      "draw only frames in which a node or an edge appears or goes (not attribute updates)");
  t->add_option("--fps", ta->options.fps, "frames per second of an MP4")
      ->check(CLI::Range(0.1, 120.0))
      ->capture_default_str();
  t->add_option("--max-frames", ta->options.max_changes,
                "draw at most this many pictures, the first ones (0: all)")
      ->check(CLI::Range(std::size_t{0}, std::size_t{1} << 32))
      ->capture_default_str();
  t->add_option("--engine", ta->engine, "layout: auto, dot, neato or sfdp")->capture_default_str();
  t->add_option("--max-width", ta->options.max_width, "picture width limit, pixels")
      ->check(CLI::Range(320, 8192))
      ->capture_default_str();
  t->add_option("--max-height", ta->options.max_height, "picture height limit, pixels")
      ->check(CLI::Range(240, 8192))
      ->capture_default_str();
  t->callback([ta] { set_exit_code(run_timeline(*ta)); });
}

}  // namespace quiver::tools
