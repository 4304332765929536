// The thesis parts shipped in examples/thesis (cutting_table.md T-3) parse into the expected IR.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <string>

#include "iso_test_util.hpp"

using namespace softmc;
using namespace softmc::program;
using namespace softmc::program::iso::test;

namespace {

Program load(const std::string& name) {
  const auto r = iso::parse_file(std::string(SOFTMC_SOURCE_DIR) + "/examples/thesis/" + name);
  for (const auto& d : r.diagnostics) ADD_FAILURE() << d.format();
  return r.program ? *r.program : Program{};
}

std::vector<core::Vec> feed_ends(const Program& p) {
  std::vector<core::Vec> out;
  for (const auto& ins : p.instructions) {
    if (const auto* l = std::get_if<Linear>(&ins.op)) out.push_back(l->end);
    if (const auto* a = std::get_if<Arc>(&ins.op)) out.push_back(a->end);
  }
  return out;
}

// Rapid first with the torch off, then M3, the cut, M5, M30: the frame every thesis part shares.
void expect_torch_frame(const Program& p) {
  ASSERT_GE(p.instructions.size(), 7u);
  EXPECT_TRUE(std::holds_alternative<Rapid>(p.instructions[0].op));
  EXPECT_EQ(op_at<MFunction>(p, 1).number, 3);
  EXPECT_TRUE(op_at<ToolSwitch>(p, 2).on);
  const std::size_t n = p.instructions.size();
  EXPECT_EQ(op_at<MFunction>(p, n - 4).number, 5);
  EXPECT_FALSE(op_at<ToolSwitch>(p, n - 3).on);
  EXPECT_EQ(op_at<MFunction>(p, n - 2).number, 30);
  EXPECT_TRUE(op_at<ProgramEnd>(p, n - 1).rewind);
  for (std::size_t i = 3; i + 4 < n; ++i) EXPECT_TRUE(is_motion(p.instructions[i].op)) << i;
}

}  // namespace

TEST(IsoThesisExamples, T3_ShieldIsThePolygonAt2MmPerSecond) {
  const auto p = load("shield.ngc");
  expect_torch_frame(p);
  EXPECT_EQ(op_at<Rapid>(p, 0).end, xyz(25, 5));
  const std::array<std::array<double, 2>, 7> kVertices{{{35, 15}, {35, 35}, {32, 37}, {16, 37}, {14, 35}, {14, 15}, {25, 5}}};
  const auto ends = feed_ends(p);
  ASSERT_EQ(ends.size(), kVertices.size());
  for (std::size_t i = 0; i < ends.size(); ++i) EXPECT_EQ(ends[i], xyz(kVertices[i][0], kVertices[i][1])) << i;
  for (std::size_t i = 3; i < 10; ++i) EXPECT_DOUBLE_EQ(op_at<Linear>(p, i).feed_mm_s, 2.0);
}

TEST(IsoThesisExamples, T3_SquareIsShiftedBy20And20At8MmPerSecond) {
  const auto p = load("square.ngc");
  expect_torch_frame(p);
  EXPECT_EQ(op_at<Rapid>(p, 0).end, xyz(20, 20));
  const auto ends = feed_ends(p);
  EXPECT_EQ(ends, (std::vector<core::Vec>{xyz(35, 20), xyz(35, 35), xyz(20, 35), xyz(20, 20)}));
  for (std::size_t i = 3; i < 7; ++i) EXPECT_DOUBLE_EQ(op_at<Linear>(p, i).feed_mm_s, 8.0);
}

TEST(IsoThesisExamples, T3_RoundedRectangleDump) {
  const auto p = load("rounded_rectangle.ngc");
  expect_torch_frame(p);
  EXPECT_EQ(dump(p),
            "start X0.000000 Y0.000000 Z0.000000\n"
            "    6:1   rapid X20.000000 Y10.000000 Z0.000000\n"
            "    7:1   m 3\n"
            "    7:1   tool on\n"
            "    8:1   feed X40.000000 Y10.000000 Z0.000000 F8.000000\n"
            "    9:1   arc X50.000000 Y20.000000 Z0.000000 CX40.000000,Y20.000000 NZ turns 1 F8.000000\n"
            "   10:1   feed X50.000000 Y40.000000 Z0.000000 F8.000000\n"
            "   11:1   arc X40.000000 Y50.000000 Z0.000000 CX40.000000,Y40.000000 NZ turns 1 F8.000000\n"
            "   12:1   feed X20.000000 Y50.000000 Z0.000000 F8.000000\n"
            "   13:1   arc X10.000000 Y40.000000 Z0.000000 CX20.000000,Y40.000000 NZ turns 1 F8.000000\n"
            "   14:1   feed X10.000000 Y20.000000 Z0.000000 F8.000000\n"
            "   15:1   arc X20.000000 Y10.000000 Z0.000000 CX20.000000,Y20.000000 NZ turns 1 F8.000000\n"
            "   16:1   m 5\n"
            "   16:1   tool off\n"
            "   17:1   m 30\n"
            "   17:1   end rewind\n");
}

TEST(IsoThesisExamples, T3_RoundedRectangleArcsAreTangentQuarterCircles) {
  const auto p = load("rounded_rectangle.ngc");
  core::Vec at = op_at<Rapid>(p, 0).end;
  int arcs = 0;
  for (const auto& ins : p.instructions) {
    if (const auto* l = std::get_if<Linear>(&ins.op)) at = l->end;
    const auto* a = std::get_if<Arc>(&ins.op);
    if (!a) continue;
    ++arcs;
    // Radius 10 at both ends, +90° counter-clockwise: (start - c) rotated by +90° is (end - c).
    const double sx = at[0] - a->center0, sy = at[1] - a->center1;
    const double ex = a->end[0] - a->center0, ey = a->end[1] - a->center1;
    EXPECT_DOUBLE_EQ(std::hypot(sx, sy), 10.0);
    EXPECT_DOUBLE_EQ(-sy, ex);
    EXPECT_DOUBLE_EQ(sx, ey);
    EXPECT_EQ(a->turns, 1);
    at = a->end;
  }
  EXPECT_EQ(arcs, 4);
  EXPECT_EQ(at, xyz(20, 10));  // closed
}

TEST(IsoThesisExamples, EveryExampleParsesCleanly) {
  for (const char* f : {"shield.ngc", "square.ngc", "rounded_rectangle.ngc"}) {
    const auto r = iso::parse_file(std::string(SOFTMC_SOURCE_DIR) + "/examples/thesis/" + f);
    EXPECT_TRUE(r.program) << f;
    EXPECT_TRUE(r.diagnostics.empty()) << f;
  }
}
