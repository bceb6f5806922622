// Poses of imported frames against an independent computation: rotation matrices composed here
// from explicit Rx, Ry, Rz (the convention both formats use, R = Rx·Ry·Rz, translations in mm),
// chained by hand, and compared with what the kinematics module's frame tree resolves through the
// imported RT edges, to 1e-9 m.

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <string>

#include "interop_test_util.h"
#include "quiver/graph/graph.h"
#include "quiver/interop/agm.h"
#include "quiver/interop/dsr.h"
#include "quiver/kinematics/frames.h"

namespace quiver::interop {
namespace {

using graph::Graph;
using graph::ReplicaId;
using M3 = std::array<std::array<double, 3>, 3>;
using V3 = std::array<double, 3>;

M3 Rx(double a) { return {{{1, 0, 0}, {0, std::cos(a), -std::sin(a)}, {0, std::sin(a), std::cos(a)}}}; }
M3 Ry(double b) { return {{{std::cos(b), 0, std::sin(b)}, {0, 1, 0}, {-std::sin(b), 0, std::cos(b)}}}; }
M3 Rz(double c) { return {{{std::cos(c), -std::sin(c), 0}, {std::sin(c), std::cos(c), 0}, {0, 0, 1}}}; }

M3 mul(const M3& A, const M3& B) {
  M3 C{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) C[i][j] += A[i][k] * B[k][j];
  return C;
}

V3 apply(const M3& A, const V3& v) {
  V3 out{};
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) out[i] += A[i][k] * v[k];
  return out;
}

/// X_WF as (R, p).
struct Frame {
  M3 R{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
  V3 p{0, 0, 0};
};

/// X_WC = X_WP · X_PC, X_PC from a translation in mm and angles (rx, ry, rz).
Frame child(const Frame& X_WP, V3 t_mm, V3 r) {
  const M3 R_PC = mul(mul(Rx(r[0]), Ry(r[1])), Rz(r[2]));
  const V3 p_PC{t_mm[0] / 1000, t_mm[1] / 1000, t_mm[2] / 1000};
  Frame X_WC;
  X_WC.R = mul(X_WP.R, R_PC);
  const V3 q = apply(X_WP.R, p_PC);
  for (int i = 0; i < 3; ++i) X_WC.p[i] = X_WP.p[i] + q[i];
  return X_WC;
}

void expect_frame(kinematics::FrameTree& tree, const std::string& root, const std::string& name, const Frame& X) {
  auto got = tree.lookup(root, name);
  ASSERT_TRUE(got.ok()) << got.error().message;
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(got->translation()[i], X.p[i], 1e-9) << name << " p[" << i << "]";
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(got->linear()(i, j), X.R[i][j], 1e-12) << name << " R(" << i << "," << j << ")";
  }
  // A point fixed in the frame, seen from the root.
  const V3 p_FQ{0.1, -0.2, 0.05};
  auto p = tree.transform_point(root, name, Eigen::Vector3d(p_FQ[0], p_FQ[1], p_FQ[2]));
  ASSERT_TRUE(p.ok());
  const V3 q = apply(X.R, p_FQ);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR((*p)[i], X.p[i] + q[i], 1e-9) << name << " point";
}

// Both fixtures hold the same chain: world -> robot (shelly) -> arm -> hand, and world -> an
// object, with these numbers (the DSR arm link is the newest sample of its history pack).
struct Chain {
  Frame robot, arm, hand, object;
};
Chain expected_chain() {
  Chain c;
  c.robot = child(Frame{}, {1200, -350.5, 80}, {0.3, -0.7, 1.1});
  c.arm = child(c.robot, {100, 200, 300}, {1.2, -0.4, 2.5});
  c.hand = child(c.arm, {0, 0, 250.25}, {-2.8, 1.4, -0.35});
  c.object = child(Frame{}, {3000, 1500, 720}, {0, 0, -1.5707963267948966});
  return c;
}

/// The chain's frames as the tree resolves them, against the computation; returns it.
Chain expect_chain(kinematics::FrameTree& tree, const std::string& robot, const std::string& object) {
  const Chain c = expected_chain();
  expect_frame(tree, "world", robot, c.robot);
  expect_frame(tree, "world", "arm", c.arm);
  expect_frame(tree, "world", "hand", c.hand);
  expect_frame(tree, "world", object, c.object);
  return c;
}

TEST(PosesTest, DsrChainMatchesTheIndependentComputation) {
  Graph g(ReplicaId{1, 1});
  ASSERT_TRUE(import_dsr_file(g, testing::fixture("dsr/current_layout.json")).ok());
  kinematics::FrameTree tree(g);
  const Chain c = expect_chain(tree, "robot", "mug");
  // Between two branches: X_mug,hand = X_W,mug⁻¹ · X_W,hand.
  auto X = tree.lookup("mug", "hand");
  ASSERT_TRUE(X.ok());
  const V3 d{c.hand.p[0] - c.object.p[0], c.hand.p[1] - c.object.p[1], c.hand.p[2] - c.object.p[2]};
  for (int i = 0; i < 3; ++i) {
    double p = 0;
    for (int k = 0; k < 3; ++k) p += c.object.R[k][i] * d[k];  // R_W,mug^T · d
    EXPECT_NEAR(X->translation()[i], p, 1e-9);
  }
}

TEST(PosesTest, AgmChainMatchesTheIndependentComputation) {
  Graph g(ReplicaId{1, 1});
  ASSERT_TRUE(import_agm_file(g, testing::fixture("agm/world.xml")).ok());
  kinematics::FrameTree tree(g);
  expect_chain(tree, "shelly", "world_7");
}

TEST(PosesTest, OlderLayoutsUseTheSameConvention) {
  Graph g(ReplicaId{1, 1});
  ASSERT_TRUE(import_dsr_file(g, testing::fixture("dsr/array_top_level_links.json")).ok());
  kinematics::FrameTree tree(g);
  const Frame base = child(Frame{}, {-1000, 0, 2500.5}, {0, -0.75, 0});
  expect_frame(tree, "world", "base", base);
  expect_frame(tree, "world", "hokuyo_base", child(base, {0, 210, 200}, {-0.1, 0, 0.2}));
  Graph h(ReplicaId{1, 1});
  ASSERT_TRUE(import_dsr_file(h, testing::fixture("dsr/symbol_object_string_codes.json")).ok());
  kinematics::FrameTree tree_h(h);
  const Frame b = child(Frame{}, {-1614.6500244140625, 0, -1597.6400146484375}, {0, 2.1238999366760254, 0});
  expect_frame(tree_h, "world", "base", b);
  expect_frame(tree_h, "world", "laser", child(b, {0, 210, 200}, {0.25, 0, -0.5}));
}

TEST(PosesTest, FilesInMetres) {
  // Nothing in a file tells its unit; a few real ones hold metres: --units m.
  const std::string xml = "<AGMModel><symbol id=\"0\" type=\"world\"/><symbol id=\"1\" type=\"f\"/>"
                          "<link src=\"0\" dst=\"1\" label=\"RT\"><linkAttribute key=\"tx\" value=\"0.031\"/>"
                          "<linkAttribute key=\"tz\" value=\"1.5\"/><linkAttribute key=\"rz\" value=\"0.5\"/>"
                          "</link></AGMModel>";
  ImportOptions metres;
  metres.unit = LengthUnit::kMetre;
  Graph g(ReplicaId{1, 1});
  ASSERT_TRUE(import_agm(g, xml, "world.xml", metres).ok());
  kinematics::FrameTree tree(g);
  expect_frame(tree, "world_0", "f_1", child(Frame{}, {31, 0, 1500}, {0, 0, 0.5}));
  ExportOptions in_metres;
  in_metres.unit = LengthUnit::kMetre;
  const std::string out = export_dsr(g, in_metres).text;
  EXPECT_NE(out.find("\"value\": [\n                                    0.031,\n                                    0.0,\n"
                     "                                    1.5\n"),
            std::string::npos)
      << out;
  EXPECT_NE(export_agm(g).text.find("<linkAttribute key=\"tz\" value=\"1500\" />"), std::string::npos);
}

TEST(PosesTest, GimbalLockAndLargeAnglesExportAndComeBack) {
  // ry = ±π/2 (rx and rz turn about one axis), and angles beyond ±π.
  for (V3 r : {V3{0.5, M_PI / 2, 0.3}, V3{-0.5, -M_PI / 2, 1.3}, V3{4.0, 2.0, -5.0}, V3{M_PI, 0, M_PI}}) {
    const std::string xml = "<AGMModel><symbol id=\"0\" type=\"world\"/><symbol id=\"1\" type=\"f\"/>"
                            "<link src=\"0\" dst=\"1\" label=\"RT\"><linkAttribute key=\"tx\" value=\"5\"/>"
                            "<linkAttribute key=\"rx\" value=\"" + std::to_string(r[0]) + "\"/>"
                            "<linkAttribute key=\"ry\" value=\"" + std::to_string(r[1]) + "\"/>"
                            "<linkAttribute key=\"rz\" value=\"" + std::to_string(r[2]) + "\"/></link></AGMModel>";
    Graph g(ReplicaId{1, 1});
    ASSERT_TRUE(import_agm(g, xml).ok());
    Graph back(ReplicaId{2, 1});
    ASSERT_TRUE(import_dsr(back, export_dsr(g).text).ok());
    kinematics::FrameTree tree(back);
    expect_frame(tree, "world_0", "f_1", child(Frame{}, {5, 0, 0}, {std::stod(std::to_string(r[0])),
                                                               std::stod(std::to_string(r[1])),
                                                               std::stod(std::to_string(r[2]))}));
  }
}

}  // namespace
}  // namespace quiver::interop
