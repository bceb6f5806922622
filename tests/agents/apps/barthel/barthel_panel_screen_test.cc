// The Panel with a real OpenCV screen (PNG files in a temporary directory) among the simulated
// Barthel agents: the panel node carries the picture the screen shows (image prefix "screen"),
// written with the `showing` mark, replicated to the other agents, replaced by the blank picture
// when the person leaves, and by the next screen when they are back.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "quiver/agents/apps/barthel/checks.h"
#include "quiver/agents/apps/barthel/grammars.h"
#include "quiver/agents/apps/barthel/barthel_roles.h"
#include "quiver/agents/apps/barthel/barthel_schema.h"
#include "quiver/agents/devices/memory_pager.h"
#include "quiver/agents/devices/memory_result_store.h"
#include "quiver/agents/devices/opencv_screen.h"
#include "quiver/agents/view/images/image_attrs.h"
#include "quiver/graph/limits.h"
#include "quiver/sim/agent_host.h"
#include "quiver/sim/simulator.h"

namespace quiver::sim {
namespace {

namespace barthel = agents::barthel;
namespace devices = agents::devices;
namespace images = agents::images;
namespace fs = std::filesystem;
using graph::Bytes;
using graph::NodeId;

constexpr std::int64_t kMs = 1'000'000;
constexpr std::int64_t kSecond = 1'000'000'000;

std::vector<std::uint8_t> read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

bool uniform(const cv::Mat& img) {
  double lo = 0, hi = 0;
  std::vector<cv::Mat> planes;
  cv::split(img, planes);
  for (const cv::Mat& p : planes) {
    cv::minMaxLoc(p, &lo, &hi);
    if (lo != hi) return false;
  }
  return true;
}

class BarthelPanelScreen : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("quiver_panel_screen_" + std::to_string(::getpid()));
    fs::remove_all(dir_);

    barthel::RoleOptions ro;
    ro.truth = [this]() -> const graph::Graph* {
      return host_ && patient_ >= 0 ? host_->graph(patient_) : nullptr;
    };
    ro.script = barthel::PatientScript::random(3);
    // The patient leaves 700 ms into the second item's question, for 4 s.
    ro.script.leaves = {{1, 700 * kMs, 4 * kSecond}};
    ro.store = &store_;
    ro.pager = &pager_;
    ro.sim_ns_per_word = 60 * kMs;
    ro.planner.answer_timeout_ns = 3 * kSecond;
    std::vector<SimAgentSpec> specs;
    for (const std::string& role : barthel::role_names()) {
      barthel::RoleOptions o = ro;
      if (role == "panel")
        o.out_dir = dir_.string();  // the real screen; every other device simulated
      specs.push_back({role, [o, role]() -> std::unique_ptr<agents::Agent> {
                         auto a = barthel::make_role(role, o);
                         return a.ok() ? std::move(*a) : nullptr;
                       }});
    }
    AgentHostOptions ho;
    ho.seed = 1;
    ho.replicator = SimConfig::default_replicator();
    ho.locks.lease_ns = kSecond;
    ho.world_json = std::string(barthel::world_json());
    host_ = std::make_unique<AgentHost>(std::move(specs), ho);
    patient_ = host_->index("patient");
    panel_ = host_->index("panel");
    ASSERT_TRUE(host_->start().ok());
  }
  void TearDown() override {
    host_.reset();
    if (!HasFailure()) fs::remove_all(dir_);
  }

  // Runs until `done` holds (checked every 10 ms of virtual time) or `limit_ns` passes.
  bool run_until(const std::function<bool()>& done, std::int64_t limit_ns = 120 * kSecond) {
    const std::int64_t end = host_->now() + limit_ns;
    while (host_->now() < end) {
      host_->run_until(host_->now() + 10 * kMs);
      if (done()) return true;
    }
    return false;
  }

  graph::Graph& replica(int i) { return *host_->graph(i); }
  NodeId panel_node(int i) { return barthel::node_id(replica(i), barthel::node::kPanel); }
  devices::OpenCvScreen& screen() {
    auto* panel = dynamic_cast<barthel::Panel*>(host_->agent(panel_));
    EXPECT_NE(panel, nullptr);
    auto* s = dynamic_cast<devices::OpenCvScreen*>(&panel->screen());
    EXPECT_NE(s, nullptr) << "the panel was given an OpenCV screen";
    return *s;
  }
  // The stored picture's bytes on replica `i` (empty when none).
  Bytes stored(int i) {
    auto info = images::image_info(replica(i), panel_node(i), barthel::kScreenImage);
    return info.ok() ? Bytes(info->bytes.begin(), info->bytes.end()) : Bytes{};
  }
  bool showing(int i) {
    return !replica(i).edges_from(panel_node(i), barthel::edge::kShowing).empty();
  }

  fs::path dir_;
  devices::MemoryResultStore store_;
  devices::MemoryPager pager_;
  std::unique_ptr<AgentHost> host_;
  int patient_ = -1, panel_ = -1;
};

TEST_F(BarthelPanelScreen, ThePanelNodeCarriesWhatTheScreenShows) {
  // Every batch on the patient's replica that brings a new `showing` mark brings the picture too:
  // they are one transaction.
  int marks = 0, marks_without_picture = 0;
  replica(patient_).subscribe([&](const graph::ChangeBatch& b) {
    for (const auto& e : b.edges) {
      if (e.kind != graph::ChangeKind::kCreated || e.key.type.str() != barthel::edge::kShowing)
        continue;
      ++marks;
      bool picture = false;
      for (const auto& n : b.nodes)
        for (const auto& a : n.attrs) picture = picture || a.str() == barthel::kScreenImage;
      if (!picture) ++marks_without_picture;
    }
  });

  // 1. The first screen: the panel node carries it, as the PNG file the screen wrote.
  ASSERT_TRUE(run_until([&] { return host_->agent(panel_) && !stored(panel_).empty(); }))
      << "the panel never stored a picture";
  const NodeId panel = panel_node(panel_);
  graph::Graph& g = replica(panel_);
  for (const char* attr : {"screen", "screen_width", "screen_height", "screen_encoding"})
    EXPECT_NE(g.attr(panel, attr), nullptr) << attr;
  EXPECT_EQ(g.get<std::int64_t>(panel, "screen_width").value(), screen().width());
  EXPECT_EQ(g.get<std::int64_t>(panel, "screen_height").value(), screen().height());
  EXPECT_EQ(g.get<std::string>(panel, "screen_encoding").value(), "png");
  ASSERT_TRUE(screen().current().has_value());
  EXPECT_TRUE(showing(panel_));
  const Bytes first = stored(panel_);
  EXPECT_EQ(first, read_file(screen().last_png())) << screen().last_png();
  EXPECT_TRUE(
      std::equal(first.begin(), first.end(), screen().image().begin(), screen().image().end()));
  std::printf("an 800x480 screen is a %zu-byte PNG (limit of one value: %llu bytes)\n",
              first.size(), static_cast<unsigned long long>(graph::limits::kMaxValueBytes));
  EXPECT_LT(first.size(), 256u << 10) << "well under the graph's limits";

  auto shown = images::get_image(g, panel, barthel::kScreenImage);
  ASSERT_TRUE(shown.ok()) << shown.error().to_string();
  EXPECT_EQ(shown->size(), cv::Size(screen().width(), screen().height()));
  EXPECT_EQ(shown->type(), CV_8UC3);
  EXPECT_FALSE(uniform(*shown));
  const cv::Mat file = cv::imread(screen().last_png(), cv::IMREAD_UNCHANGED);
  EXPECT_EQ(cv::norm(*shown, file, cv::NORM_INF), 0);

  // Replicated: the patient's replica (a viewer would be one more) holds the same bytes.
  ASSERT_TRUE(run_until([&] { return stored(patient_) == first; }, 2 * kSecond));

  // 2. The person leaves: the screen clears, and the picture becomes the blank one it shows.
  // (The screen also clears for an instant between two prompts; this waits for the leave.)
  ASSERT_TRUE(run_until([&] { return !barthel::patient_present_truth(replica(patient_)); }))
      << "the patient never left";
  ASSERT_TRUE(
      run_until([&] { return !screen().current().has_value() && !showing(panel_); }, kSecond))
      << "the screen was not cleared when the person left";
  auto blank = images::get_image(g, panel, barthel::kScreenImage);
  ASSERT_TRUE(blank.ok()) << blank.error().to_string();
  EXPECT_EQ(blank->size(), cv::Size(screen().width(), screen().height()));
  EXPECT_TRUE(uniform(*blank));
  EXPECT_EQ(stored(panel_), read_file(screen().last_png()));
  const Bytes cleared = stored(panel_);
  std::printf("the blank screen is a %zu-byte PNG\n", cleared.size());
  ASSERT_TRUE(run_until([&] { return stored(patient_) == cleared; }, 2 * kSecond));

  // 3. Back in the chair: the next screen replaces the blank picture.
  ASSERT_TRUE(run_until([&] { return barthel::patient_present_truth(replica(patient_)); }));
  ASSERT_TRUE(run_until([&] { return screen().current().has_value() && showing(panel_); }))
      << "the screen never showed the question again";
  auto again = images::get_image(g, panel, barthel::kScreenImage);
  ASSERT_TRUE(again.ok()) << again.error().to_string();
  EXPECT_FALSE(uniform(*again));
  EXPECT_EQ(stored(panel_), read_file(screen().last_png()));

  EXPECT_GE(marks, 2);
  EXPECT_EQ(marks_without_picture, 0);
  EXPECT_EQ(host_->rejected(), 0u) << "every replica accepted the panel's deltas";
}

}  // namespace
}  // namespace quiver::sim
