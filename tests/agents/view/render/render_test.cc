// Pictures of a world graph: the geometric-part rule, the type colours, and what the DOT, SVG
// and PNG files hold (structure, not exact pixels). Real files in a temporary folder.

#include "quiver/agents/view/render/render.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <regex>
#include <set>
#include <sstream>

#include "quiver/agents/view/render/geometric_part.h"
#include "quiver/agents/view/render/layout.h"
#include "quiver/agents/view/render/type_colour.h"
#include "sample_world.h"

namespace quiver::agents::render {
namespace {

namespace fs = std::filesystem;
using graph::Graph;
using graph::NodeId;

std::string temp_path(const std::string& name) {
  const fs::path dir =
      fs::temp_directory_path() / ("quiver_render_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return (dir / name).string();
}

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

struct Sample {
  Graph g{graph::ReplicaId{1, 1}};
  Sample() { render_test::build_sample_world(g); }
  NodeId id(const char* name) const { return *g.find_node(name); }
};

// The statement of one node in Graphviz's DOT output: from its name to the closing "];".
std::string dot_statement(const std::string& dot, const std::string& head) {
  const auto at = dot.find("\n\t" + head + "\t[");
  if (at == std::string::npos) return "";
  return dot.substr(at, dot.find("];", at) - at);
}

// The <g> element of the SVG node or edge whose <title> is `title`.
std::string svg_group(const std::string& svg, const std::string& title) {
  const auto t = svg.find("<title>" + title + "</title>");
  if (t == std::string::npos) return "";
  const auto open = svg.rfind("<g ", t);
  return svg.substr(open, svg.find("</g>", t) - open);
}

TEST(GeometricPartTest, RtEdgesAndNodesOnlyInTheTreeAreGeometry) {
  Sample s;
  EXPECT_TRUE(is_geometric(s.g, s.id("world")));   // RT children only
  EXPECT_TRUE(is_geometric(s.g, s.id("camera")));  // an RT parent only
  EXPECT_FALSE(is_geometric(s.g, s.id("robot")));  // RT edges, but also `in`
  EXPECT_FALSE(is_geometric(s.g, s.id("kitchen")));
  EXPECT_FALSE(is_geometric(s.g, s.id("mug")));   // symbolic only
  EXPECT_FALSE(is_geometric(s.g, s.id("note")));  // no edges at all
  EXPECT_FALSE(is_geometric(s.g, NodeId{}));      // not in the graph
  EXPECT_TRUE(is_geometric(graph::EdgeKey{s.id("world"), s.id("robot"), graph::symbols::rt()}));
  EXPECT_FALSE(is_geometric(graph::EdgeKey{s.id("robot"), s.id("kitchen"), graph::Symbol("in")}));
  EXPECT_TRUE(is_geometric_edge_type("RT"));
  EXPECT_FALSE(is_geometric_edge_type("in"));
  static_assert(is_geometric_node(false, true) && !is_geometric_node(true, true) &&
                !is_geometric_node(false, false) && !is_geometric_node(true, false));
}

TEST(GeometricPartTest, ANodeBecomesGeometricWhenItsLastSymbolicEdgeGoes) {
  Sample s;
  auto tx = s.g.begin();
  ASSERT_TRUE(tx.delete_edge(s.id("robot"), s.id("kitchen"), "in").ok());
  ASSERT_TRUE(tx.commit().ok());
  EXPECT_TRUE(is_geometric(s.g, s.id("robot")));
}

TEST(TypeColourTest, StableLightAndDistinct) {
  // Pinned: the web viewer and old pictures agree with these (a palette change shows here).
  EXPECT_EQ(css_hex(type_colour("robot")), css_hex(type_colour(std::string("rob") + "ot")));
  EXPECT_EQ(css_hex(type_colour("robot")), "#f1e2cc");
  EXPECT_EQ(css_hex(type_colour("room")), "#fbb4ae");
  EXPECT_EQ(css_hex(Rgb{1, 0xab, 255}), "#01abff");
  std::set<std::string> seen;
  for (const char* t :
       {"robot", "room", "person", "mug", "table", "camera", "world", "test", "panel", "joint"}) {
    const Rgb c = type_colour(t);
    EXPECT_GE(c.r + c.g + c.b, 3 * 0x80) << t << " is too dark for black text";
    const Rgb s = type_stroke_colour(t);
    EXPECT_LT(s.r + s.g + s.b, c.r + c.g + c.b) << t;
    seen.insert(css_hex(c));
  }
  EXPECT_GE(seen.size(), 6u);
}

TEST(PictureTest, HideGeometryLeavesOutRtEdgesAndGeometricNodes) {
  Sample s;
  Picture all = make_picture(s.g);
  EXPECT_EQ(all.nodes.size(), 7u);
  EXPECT_EQ(all.edges.size(), 6u);  // 3 RT + 3 symbolic
  PictureOptions o;
  o.hide_geometry = true;
  o.highlight_nodes.insert(s.id("robot"));
  Picture p = make_picture(s.g, o);
  std::set<std::string> names;
  for (const PictureNode& n : p.nodes) {
    names.insert(n.name);
    EXPECT_EQ(n.highlighted, n.name == "robot");
  }
  EXPECT_EQ(names, (std::set<std::string>{"kitchen", "mug", "note", "robot", "table"}));
  ASSERT_EQ(p.edges.size(), 3u);
  for (const PictureEdge& e : p.edges) EXPECT_NE(e.type, "RT");
  EXPECT_EQ(node_label(p.nodes[0]), "kitchen\n(room)");
}

TEST(RenderTest, DotHoldsEveryNodeEdgeLabelAndPosition) {
  Sample s;
  RenderOptions o;
  o.picture.title = "the sample";
  o.picture.highlight_nodes.insert(s.id("robot"));
  o.picture.highlight_edges.insert(graph::EdgeKey{s.id("mug"), s.id("table"), graph::Symbol("on")});
  const std::string path = temp_path("sample.dot");
  ASSERT_TRUE(render_file(s.g, o, path).ok());
  const std::string dot = read_text(path);
  for (const char* n : {"world", "kitchen", "robot", "camera", "mug", "table", "note"}) {
    const std::string st = dot_statement(dot, n);
    ASSERT_FALSE(st.empty()) << n << " missing in\n" << dot;
    EXPECT_NE(st.find("pos="), std::string::npos) << st;
  }
  EXPECT_NE(dot.find("label=\"robot\\n(robot)\""), std::string::npos);
  for (const char* e : {"label=in", "label=on", "label=RT"})
    EXPECT_NE(dot.find(e), std::string::npos) << e;
  EXPECT_NE(dot.find("label=\"the sample\""), std::string::npos);
  const std::string robot = dot_statement(dot, "robot");
  EXPECT_NE(robot.find("penwidth=3"), std::string::npos) << robot;
  EXPECT_NE(robot.find("color=\"#d62728\""), std::string::npos) << robot;
  EXPECT_EQ(dot_statement(dot, "mug").find("penwidth=3"), std::string::npos);
  const std::string on = dot_statement(dot, "mug -> table");
  EXPECT_NE(on.find("penwidth=3"), std::string::npos) << on;
  EXPECT_EQ(dot_statement(dot, "table -> kitchen").find("penwidth=3"), std::string::npos);
  EXPECT_NE(dot_statement(dot, "world -> robot").find("style=dashed"), std::string::npos);
}

TEST(RenderTest, DotWithHiddenGeometryHasNoGeometricNodeOrRtEdge) {
  Sample s;
  RenderOptions o;
  o.picture.hide_geometry = true;
  const std::string path = temp_path("hidden.dot");
  ASSERT_TRUE(render_file(s.g, o, path).ok());
  const std::string dot = read_text(path);
  EXPECT_TRUE(dot_statement(dot, "world").empty()) << dot;
  EXPECT_TRUE(dot_statement(dot, "camera").empty()) << dot;
  EXPECT_EQ(dot.find("RT"), std::string::npos) << dot;
  for (const char* n : {"kitchen", "robot", "mug", "table", "note"})
    EXPECT_FALSE(dot_statement(dot, n).empty()) << n;
}

TEST(RenderTest, SvgHoldsNamesEdgeLabelsAndHighlightStyling) {
  Sample s;
  RenderOptions o;
  o.picture.highlight_nodes.insert(s.id("robot"));
  const std::string path = temp_path("sample.svg");
  ASSERT_TRUE(render_file(s.g, o, path).ok());
  const std::string svg = read_text(path);
  ASSERT_EQ(svg.rfind("<?xml", 0), 0u) << svg.substr(0, 100);
  for (const char* n : {"world", "kitchen", "robot", "camera", "mug", "table", "note"}) {
    const std::string g = svg_group(svg, n);
    ASSERT_FALSE(g.empty()) << n;
    EXPECT_NE(g.find(std::string(">") + n + "</text>"), std::string::npos) << g;
  }
  for (const char* t : {">in</text>", ">on</text>", ">RT</text>"})
    EXPECT_NE(svg.find(t), std::string::npos) << t;
  const std::string robot = svg_group(svg, "robot");
  EXPECT_NE(robot.find("class=\"node highlight\""), std::string::npos) << robot;
  EXPECT_NE(robot.find("stroke=\"#d62728\""), std::string::npos) << robot;
  EXPECT_NE(robot.find("stroke-width=\"3\""), std::string::npos) << robot;
  EXPECT_NE(robot.find("fill=\"" + css_hex(type_colour("robot")) + "\""), std::string::npos)
      << robot;
  const std::string mug = svg_group(svg, "mug");
  EXPECT_EQ(mug.find("#d62728"), std::string::npos) << mug;
  // RT edges dashed grey.
  const std::string rt = svg_group(svg, "world&#45;&gt;robot");
  EXPECT_NE(rt.find("stroke-dasharray"), std::string::npos) << rt;
  EXPECT_NE(rt.find(css_hex(kGeometryColour)), std::string::npos) << rt;
}

TEST(RenderTest, SvgWithHiddenGeometryLeavesOutGeometricNames) {
  Sample s;
  RenderOptions o;
  o.picture.hide_geometry = true;
  auto svg = render_text(s.g, o, TextFormat::kSvg);
  ASSERT_TRUE(svg.ok()) << svg.error().to_string();
  EXPECT_EQ(svg->find(">camera</text>"), std::string::npos);
  EXPECT_EQ(svg->find(">world</text>"), std::string::npos);
  EXPECT_EQ(svg->find(">RT</text>"), std::string::npos);
  EXPECT_NE(svg->find(">robot</text>"), std::string::npos);
}

int pixels_near(const cv::Mat& img, Rgb c, int tolerance = 6) {
  int n = 0;
  for (int y = 0; y < img.rows; ++y)
    for (int x = 0; x < img.cols; ++x) {
      const cv::Vec3b p = img.at<cv::Vec3b>(y, x);
      if (std::abs(p[2] - c.r) <= tolerance && std::abs(p[1] - c.g) <= tolerance &&
          std::abs(p[0] - c.b) <= tolerance)
        ++n;
    }
  return n;
}

TEST(RenderTest, PngHasAReasonableSizeAndTheTypeAndHighlightColours) {
  Sample s;
  RenderOptions o;
  o.picture.highlight_nodes.insert(s.id("robot"));
  const std::string path = temp_path("sample.png");
  ASSERT_TRUE(render_file(s.g, o, path).ok());
  const cv::Mat img = cv::imread(path, cv::IMREAD_COLOR);
  ASSERT_FALSE(img.empty());
  EXPECT_GT(img.cols, 200);
  EXPECT_GT(img.rows, 150);
  EXPECT_LT(img.cols, 2000);
  EXPECT_LT(img.rows, 2000);
  // Not blank: every type's fill shows (an ellipse of a few hundred pixels at least).
  for (const char* t : {"robot", "room", "mug", "table", "camera", "world", "note"})
    EXPECT_GT(pixels_near(img, type_colour(t)), 300) << t;
  EXPECT_GT(pixels_near(img, kHighlightColour, 20), 100);
  EXPECT_GT(pixels_near(img, kGeometryColour, 20), 20);  // dashed RT edges

  RenderOptions plain;
  auto bytes = render_png(s.g, plain);
  ASSERT_TRUE(bytes.ok());
  const cv::Mat other = cv::imdecode(*bytes, cv::IMREAD_COLOR);
  EXPECT_EQ(pixels_near(other, kHighlightColour, 20), 0) << "nothing asked to be highlighted";
}

TEST(RenderTest, PngOfHiddenGeometryLacksTheGeometricTypes) {
  Sample s;
  RenderOptions o;
  o.picture.hide_geometry = true;
  auto bytes = render_png(s.g, o);
  ASSERT_TRUE(bytes.ok());
  const cv::Mat img = cv::imdecode(*bytes, cv::IMREAD_COLOR);
  EXPECT_GT(pixels_near(img, type_colour("robot")), 300);
  bool camera_colour_unique = true;
  for (const char* t : {"robot", "room", "mug", "table", "note"})
    camera_colour_unique = camera_colour_unique && !(type_colour("camera") == type_colour(t));
  if (camera_colour_unique) {
    EXPECT_EQ(pixels_near(img, type_colour("camera"), 0), 0);
  }
  EXPECT_EQ(pixels_near(img, kGeometryColour, 0), 0);
}

TEST(RenderTest, ErrorsNameTheFileAndTheExtension) {
  Sample s;
  const std::string jpg = temp_path("picture.jpg");
  Status st = render_file(s.g, {}, jpg);
  ASSERT_FALSE(st.ok());
  EXPECT_EQ(st.error().code, ErrorCode::kInvalidArgument);
  EXPECT_NE(st.error().message.find("'" + jpg + "'"), std::string::npos) << st.error().message;
  EXPECT_NE(st.error().message.find("'.jpg'"), std::string::npos) << st.error().message;
  EXPECT_FALSE(fs::exists(jpg));

  for (const char* name :
       {"no/such/folder/x.svg", "no/such/folder/x.png", "no/such/folder/x.dot"}) {
    const std::string path = temp_path(name);
    st = render_file(s.g, {}, path);
    ASSERT_FALSE(st.ok()) << name;
    EXPECT_EQ(st.error().code, ErrorCode::kIo) << name;
    EXPECT_NE(st.error().message.find(path), std::string::npos) << st.error().message;
  }
  auto e = parse_engine("circo");
  ASSERT_FALSE(e.ok());
  EXPECT_NE(e.error().message.find("'circo'"), std::string::npos);
  EXPECT_EQ(*parse_engine("sfdp"), Engine::kSfdp);
}

TEST(LayoutTest, EveryEnginePlacesEveryNodeInsideTheDrawing) {
  Sample s;
  const Picture p = make_picture(s.g);
  for (Engine e : {Engine::kDot, Engine::kNeato, Engine::kSfdp}) {
    auto l = lay_out(p, e);
    ASSERT_TRUE(l.ok()) << to_string(e) << ": " << l.error().to_string();
    EXPECT_EQ(l->engine, e);
    ASSERT_EQ(l->nodes.size(), p.nodes.size());
    ASSERT_EQ(l->edges.size(), p.edges.size());
    std::set<std::pair<long, long>> places;
    for (const NodePlace& n : l->nodes) {
      EXPECT_GE(n.centre.x, 0);
      EXPECT_LE(n.centre.x, l->width);
      EXPECT_GE(n.centre.y, 0);
      EXPECT_LE(n.centre.y, l->height);
      EXPECT_GT(n.width, 20);
      places.emplace(std::lround(n.centre.x), std::lround(n.centre.y));
    }
    EXPECT_EQ(places.size(), p.nodes.size()) << to_string(e) << ": two nodes at one place";
    for (const EdgePlace& ep : l->edges) {
      EXPECT_GE(ep.curve.size(), 2u) << to_string(e);
      EXPECT_TRUE(ep.arrow) << to_string(e);
    }
  }
  EXPECT_EQ(resolve_engine(Engine::kAuto, 10), Engine::kDot);
  EXPECT_EQ(resolve_engine(Engine::kAuto, kDotMaxNodes + 1), Engine::kSfdp);
}

TEST(LayoutTest, DotRanksTheKinematicTreeTopDown) {
  Sample s;
  const Picture p = make_picture(s.g);
  auto l = lay_out(p, Engine::kDot);
  ASSERT_TRUE(l.ok());
  auto y = [&](const char* name) {
    for (std::size_t i = 0; i < p.nodes.size(); ++i)
      if (p.nodes[i].name == name) return l->nodes[i].centre.y;
    return -1.0;
  };
  EXPECT_LT(y("world"), y("robot"));
  EXPECT_LT(y("robot"), y("camera"));
}

TEST(LayoutTest, FittingAFrameLaysAWideLayerAcross) {
  Graph g(graph::ReplicaId{4, 1});
  auto tx = g.begin();
  const NodeId hub = *tx.create_node("test", "hub");
  for (int i = 0; i < 20; ++i)
    ASSERT_TRUE(
        tx.insert_edge(hub, *tx.create_node("utterance", "u" + std::to_string(i)), "said").ok());
  ASSERT_TRUE(tx.commit().ok());
  const Picture p = make_picture(g);
  auto down = lay_out(p, Engine::kDot);
  ASSERT_TRUE(down.ok());
  EXPECT_GT(down->width, 3 * down->height);  // one wide layer under the hub
  auto fit = lay_out_to_fit(p, Engine::kDot, 800, 800);
  ASSERT_TRUE(fit.ok());
  EXPECT_GT(fit->height, fit->width);                      // laid across: the layer runs down
  auto wide = lay_out_to_fit(p, Engine::kDot, 4000, 400);  // a wide frame keeps top-down
  ASSERT_TRUE(wide.ok());
  EXPECT_DOUBLE_EQ(wide->width, down->width);
  EXPECT_DOUBLE_EQ(wide->height, down->height);
}

// A generated world of 2,000 nodes: 1,999 RT edges and 1,000 symbolic ones.
TEST(LayoutTest, TwoThousandNodesRenderInSeconds) {
  Graph g(graph::ReplicaId{3, 1});
  const char* types[] = {"room",  "robot", "person", "mug",    "table",
                         "chair", "door",  "sensor", "camera", "joint"};
  const char* relations[] = {"in", "on", "near", "sees", "holds"};
  std::vector<NodeId> ids;
  std::uint64_t r = 12345;
  auto next = [&r] { return (r = r * 6364136223846793005ull + 1442695040888963407ull) >> 33; };
  auto tx = g.begin();
  for (int i = 0; i < 2000; ++i) {
    ids.push_back(*tx.create_node(types[next() % 10], "n" + std::to_string(i)));
    if (i > 0) {
      ASSERT_TRUE(tx.set_rt(ids[next() % i], ids[i], graph::Pose::identity()).ok());
    }
  }
  for (int k = 0; k < 1000; ++k) {
    const auto a = next() % 2000, b = next() % 2000;
    if (a != b) (void)tx.insert_edge(ids[a], ids[b], relations[next() % 5]);
  }
  ASSERT_TRUE(tx.commit().ok());
  const auto t0 = std::chrono::steady_clock::now();
  RenderOptions o;  // auto: sfdp
  const std::string path = temp_path("big.png");
  ASSERT_TRUE(render_file(g, o, path).ok());
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("2000 nodes, auto engine (%s), PNG: %.2f s\n",
              to_string(resolve_engine(Engine::kAuto, 2000)), s);
  EXPECT_LT(s, 60.0);
  const cv::Mat img = cv::imread(path, cv::IMREAD_COLOR);
  ASSERT_FALSE(img.empty());
  EXPECT_LE(std::max(img.cols, img.rows), o.max_side_px);
  EXPECT_GT(std::max(img.cols, img.rows), 1000);
}

}  // namespace
}  // namespace quiver::agents::render
