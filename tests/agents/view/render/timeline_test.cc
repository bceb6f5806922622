// The timeline of a recording: one picture per change that changes something drawn, a stable
// layout of everything that ever appears, captions naming the changes, PNG pictures or an MP4
// that OpenCV reads back with the same change count; and replaying a recording change by change.

#include "quiver/agents/view/render/timeline_video.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

#include "quiver/agents/view/recording/record_file.h"
#include "quiver/agents/view/render/render_replay.h"
#include "quiver/agents/view/render/type_colour.h"
#include "sample_world.h"

namespace quiver::agents::render {
namespace {

namespace fs = std::filesystem;

std::string temp_path(const std::string& name) {
  const fs::path dir =
      fs::temp_directory_path() / ("quiver_timeline_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return (dir / name).string();
}

std::vector<std::string> pngs_in(const std::string& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".png") out.push_back(e.path().filename().string());
  std::sort(out.begin(), out.end());
  return out;
}

bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

TEST(ReplayTest, StepsThroughTheFramesTellingWhatEachChanged) {
  const auto changes = render_test::sample_frames();
  ASSERT_EQ(changes.size(), 5u);
  Replay r(changes);
  EXPECT_EQ(r.step().nodes.size(), 7u);  // the initial state: every node created
  EXPECT_EQ(r.graph().node_count(), 7u);
  const graph::ChangeBatch& b = r.step();
  EXPECT_EQ(b.origin_name, "planner");
  ASSERT_EQ(b.nodes.size(), 1u);
  EXPECT_EQ(b.nodes[0].kind, graph::ChangeKind::kCreated);
  EXPECT_EQ(r.graph().node_count(), 8u);
  r.run_through(4);
  EXPECT_TRUE(r.done());
  EXPECT_EQ(r.graph().node_count(), 7u);
  EXPECT_FALSE(r.graph().find_node("person").has_value());
}

TEST(TimelineTest, PngFramesOneForEachFrameWithCaptions) {
  const auto changes = render_test::sample_frames();
  const std::string dir = temp_path("all");
  auto info = render_timeline(changes, {}, dir + "/");
  ASSERT_TRUE(info.ok()) << info.error().to_string();
  EXPECT_EQ(info->recorded, 5u);
  EXPECT_EQ(info->written, 5u);
  EXPECT_EQ(info->skipped, 0u);
  EXPECT_EQ(info->nodes, 8u);  // person, gone at the end, is laid out too
  EXPECT_EQ(pngs_in(dir),
            (std::vector<std::string>{"0000.png", "0001.png", "0002.png", "0003.png", "0004.png"}));
  ASSERT_EQ(info->captions.size(), 5u);
  EXPECT_TRUE(
      contains(info->captions[0], "t = 0.00 s  origin: loader  initial state: 7 nodes, 6 edges"))
      << info->captions[0];
  EXPECT_TRUE(
      contains(info->captions[1],
               "t = 1.50 s  origin: planner  created person (person), added person -with-> robot"))
      << info->captions[1];
  EXPECT_TRUE(contains(info->captions[2], "origin: speech  set speaking on robot"))
      << info->captions[2];
  EXPECT_TRUE(contains(info->captions[3], "moved camera")) << info->captions[3];
  EXPECT_TRUE(contains(info->captions[4], "deleted person")) << info->captions[4];
  EXPECT_TRUE(contains(info->captions[4], "removed person -with-> robot")) << info->captions[4];

  // One size for every picture; the changed node drawn in the highlight colour, the first not.
  cv::Mat first = cv::imread(dir + "/0000.png"), second = cv::imread(dir + "/0001.png");
  ASSERT_FALSE(first.empty());
  EXPECT_EQ(first.cols, info->width);
  EXPECT_EQ(first.rows, info->height);
  EXPECT_EQ(second.size(), first.size());
  auto red = [](const cv::Mat& m) {
    cv::Mat mask;
    const Rgb c = kHighlightColour;
    cv::inRange(m, cv::Scalar(c.b - 20, c.g - 20, c.r - 20),
                cv::Scalar(c.b + 20, c.g + 20, c.r + 20), mask);
    return cv::countNonZero(mask);
  };
  EXPECT_EQ(red(first), 0);
  EXPECT_GT(red(second), 100);
}

TEST(TimelineTest, HidingGeometrySkipsFramesThatOnlyMoveThings) {
  const auto changes = render_test::sample_frames();
  TimelineOptions o;
  o.hide_geometry = true;
  const std::string dir = temp_path("hidden");
  auto info = render_timeline(changes, o, dir);
  ASSERT_TRUE(info.ok()) << info.error().to_string();
  EXPECT_EQ(info->written, 4u);
  EXPECT_EQ(info->skipped, 1u);
  EXPECT_EQ(info->changes, (std::vector<std::size_t>{0, 1, 2, 4}));
  EXPECT_EQ(info->nodes, 6u);  // kitchen robot mug table note person
  EXPECT_EQ(pngs_in(dir).size(), 4u);
  for (const std::string& c : info->captions) EXPECT_FALSE(contains(c, "camera")) << c;

  o.every_change = true;
  info = render_timeline(changes, o, dir);
  ASSERT_TRUE(info.ok());
  EXPECT_EQ(info->written, 5u);
  EXPECT_EQ(pngs_in(dir).size(), 5u);

  // A shorter run into the same folder leaves no changes of the longer one behind.
  o.every_change = false;
  o.max_changes = 2;
  info = render_timeline(changes, o, dir);
  ASSERT_TRUE(info.ok());
  EXPECT_EQ(info->written, 2u);
  EXPECT_EQ(info->cut, 2u);
  EXPECT_EQ(pngs_in(dir), (std::vector<std::string>{"0000.png", "0001.png"}));
}

TEST(TimelineTest, StructureOnlyDrawsFramesWhereSomethingAppearsOrGoes) {
  const auto changes = render_test::sample_frames();
  TimelineOptions o;
  o.structure_only = true;
  o.every_change = true;  // overridden
  auto info = render_timeline(changes, o, temp_path("structure"));
  ASSERT_TRUE(info.ok()) << info.error().to_string();
  EXPECT_EQ(info->changes, (std::vector<std::size_t>{0, 1, 4}));
  EXPECT_EQ(info->skipped, 2u);
}

TEST(TimelineTest, Mp4ReopensWithTheFrameCount) {
  const auto changes = render_test::sample_frames();
  const std::string path = temp_path("run.mp4");
  TimelineOptions o;
  o.fps = 4;
  auto info = render_timeline(changes, o, path);
  ASSERT_TRUE(info.ok()) << info.error().to_string();
  cv::VideoCapture in(path);
  ASSERT_TRUE(in.isOpened()) << path;
  EXPECT_EQ(static_cast<int>(in.get(cv::CAP_PROP_FRAME_COUNT)), 5);
  EXPECT_EQ(static_cast<int>(in.get(cv::CAP_PROP_FRAME_WIDTH)), info->width);
  EXPECT_EQ(static_cast<int>(in.get(cv::CAP_PROP_FRAME_HEIGHT)), info->height);
  EXPECT_NEAR(in.get(cv::CAP_PROP_FPS), 4.0, 0.01);
  int decoded = 0;
  for (cv::Mat m; in.read(m);) ++decoded;
  EXPECT_EQ(decoded, 5);
}

TEST(TimelineTest, ARecordingFileRoundTrips) {
  const std::string path = temp_path("sample.qrec");
  {
    const auto bytes = render_test::sample_recording_bytes();
    std::ofstream out(path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(bytes.data()),
              static_cast<std::streamsize>(bytes.size()));
  }
  auto rec = recording::read_recording(path);
  ASSERT_TRUE(rec.ok()) << rec.error().to_string();
  auto info = render_timeline(rec->changes, {}, temp_path("from_file"));
  ASSERT_TRUE(info.ok()) << info.error().to_string();
  EXPECT_EQ(info->written, 5u);
}

TEST(TimelineTest, ErrorsNameTheOutput) {
  const auto changes = render_test::sample_frames();
  const std::string gif = temp_path("run.gif");
  auto info = render_timeline(changes, {}, gif);
  ASSERT_FALSE(info.ok());
  EXPECT_EQ(info.error().code, ErrorCode::kInvalidArgument);
  EXPECT_TRUE(contains(info.error().message, "'" + gif + "'")) << info.error().message;
  EXPECT_TRUE(contains(info.error().message, "'.gif'")) << info.error().message;

  info = render_timeline({}, {}, temp_path("empty"));
  ASSERT_FALSE(info.ok());
  EXPECT_TRUE(contains(info.error().message, "no frames"));

  const std::string blocked = temp_path("a_file");
  std::ofstream(blocked) << "x";
  info = render_timeline(changes, {}, blocked + "/frames/");
  ASSERT_FALSE(info.ok());
  EXPECT_EQ(info.error().code, ErrorCode::kIo);
  EXPECT_TRUE(contains(info.error().message, blocked)) << info.error().message;

  info = render_timeline(changes, {}, temp_path("no/such/folder/run.mp4"));
  ASSERT_FALSE(info.ok());
  EXPECT_EQ(info.error().code, ErrorCode::kIo);
  EXPECT_TRUE(contains(info.error().message, "no/such/folder/run.mp4")) << info.error().message;
}

}  // namespace
}  // namespace quiver::agents::render
