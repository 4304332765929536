// ISO polar coordinates @ (radius) and ^ (angle): the end points and errors of LinuxCNC 2.9. The
// expected values are what LinuxCNC's `rs274 -g` printed for the same programs (4 decimals in program
// units; rs274 prints program coordinates, softmc's IR holds machine coordinates in mm).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "iso_test_util.hpp"

using namespace softmc;
using namespace softmc::program;
using namespace softmc::program::iso::test;

namespace {

constexpr double kRs274 = 1e-4;  // rs274 prints 4 decimals

// Every end point against rs274's (x, y, z) rows, scaled by `k` (25.4 for inch programs).
void expect_ends(const Program& p, const std::vector<std::vector<double>>& want, double k = 1.0) {
  const auto got = ends(p);
  ASSERT_EQ(got.size(), want.size());
  for (std::size_t i = 0; i < want.size(); ++i)
    for (std::size_t a = 0; a < want[i].size(); ++a)
      EXPECT_NEAR(got[i][a], want[i][a] * k, kRs274 * k) << "move " << i << " axis " << core::letter(a);
}

}  // namespace

TEST(IsoPolar, G90RadiusAndAngleAngleAloneAndRadiusAlone) {
  // LinuxCNC find_ends, G90: @r ^t is (r cos t, r sin t); @ alone keeps the current angle, ^ alone
  // the current radius; both about the origin of the coordinate system. Values may be expressions.
  const auto p = parse_ok(
      "G21 G90 G17\nG0 X10 Y0\nG0 @5 ^30\nG0 @8\nG0 ^120\nG1 @[2*3] ^[45] Z1 F100\n");
  expect_ends(p, {{10, 0, 0}, {4.3301, 2.5, 0}, {6.9282, 4, 0}, {-4, 6.9282, 0}, {4.2426, 4.2426, 1}});
}

TEST(IsoPolar, G91StepsTheRadiusThenTheAngleAboutTheOriginNotTheCurrentPoint) {
  // LinuxCNC find_ends, G91: @dr adds to the current radius, ^dt to the current angle (radius first
  // when both are given); a radius through zero comes out on the other side of the origin.
  const auto p = parse_ok("G21 G90 G17\nG0 X10 Y0\nG91 G0 @2\nG0 ^90\nG0 @-2 ^-45\nG0 ^30 Z1\nG0 @-12\n");
  expect_ends(p, {{10, 0, 0}, {12, 0, 0}, {0, 12, 0}, {7.0711, 7.0711, 0}, {2.5882, 9.6593, 1}, {-0.5176, -1.9319, 1}});
}

TEST(IsoPolar, G20ScalesTheRadiusButNotTheAngle) {
  const auto p = parse_ok("G20 G90 G17\nG0 X1 Y0\nG0 @2 ^60\nG91 G0 @0.5 ^30\n");
  expect_ends(p, {{1, 0, 0}, {1, 1.7321, 0}, {0, 2.5, 0}}, 25.4);
}

TEST(IsoPolar, OtherAxesMoveAsWithXAndYWords) {
  const auto p = parse_ok("G21 G90 G17\nG0 X10 Y0 A5\nG1 @10 ^45 A10 Z-1 F100\nG91 G0 ^10 A-1\n");
  const auto e = ends(p);
  ASSERT_EQ(e.size(), 3u);
  EXPECT_NEAR(e[1][0], 7.0711, kRs274);
  EXPECT_NEAR(e[1][1], 7.0711, kRs274);
  EXPECT_EQ(e[1][2], -1);
  EXPECT_EQ(e[1][3], 10);  // A in degrees
  EXPECT_NEAR(e[2][0], 5.7358, kRs274);
  EXPECT_NEAR(e[2][1], 8.1915, kRs274);
  EXPECT_EQ(e[2][3], 9);
}

TEST(IsoPolar, ArcsTakeTheirEndPointFromPolarCoordinates) {
  // rs274: centre format, R format with polar words only (not "X and Y words missing"), a helix, G91
  // and G90.1 centres, and P turns.
  const auto p = parse_ok(
      "G21 G90 F300\nG0 X10 Y0\nG3 @10 ^90 I-10 J0\nG3 ^180 I0 J-10\nG2 ^90 R10 Z-1\n"
      "G91 G2 ^-90 I0 J-10 Z-1\nG3 @0 ^180 I-10 J0 P2\nG90 G2 @5 R-20\nG3 @15 ^30 R15\nG90.1 G2 ^10 I0 J0\n");
  expect_ends(p, {{10, 0, 0},
                  {0, 10, 0},
                  {-10, 0, 0},
                  {0, 10, -1},
                  {10, 0, -2},
                  {-10, 0, -2},
                  {-5, 0, -2},
                  {12.9904, 7.5, -2},
                  {14.7721, 2.6047, -2}});
  std::vector<Arc> arcs;
  for (const auto& i : p.instructions)
    if (const auto* a = std::get_if<Arc>(&i.op)) arcs.push_back(*a);
  ASSERT_EQ(arcs.size(), 8u);
  const double centres[8][2] = {{0, 0}, {0, 0}, {0, 0}, {0, 0}, {0, 0}, {-7.5, 19.8431}, {-0.3925, 14.2748}, {0, 0}};
  for (std::size_t i = 0; i < arcs.size(); ++i) {
    EXPECT_NEAR(arcs[i].center0, centres[i][0], kRs274) << "arc " << i;
    EXPECT_NEAR(arcs[i].center1, centres[i][1], kRs274) << "arc " << i;
  }
  EXPECT_EQ(arcs[4].turns, 2);  // rs274 rotation 2: counter-clockwise, two turns
}

TEST(IsoPolar, SplinesG5AndG51EndThere) {
  const auto p = parse_ok(
      "G21 G90 F100\nG0 X10 Y0\nG5.1 @5 ^90 I-2 J3\nG1 Z1\nG5 @5 ^180 I-2 J3 P1 Q2\nG1 Z2\nG91 G5.1 ^90 I1 J-2\nG1 Z3\n");
  const auto e = ends(p);
  ASSERT_EQ(e.size(), 7u);
  EXPECT_NEAR(e[2][0], 0, 1e-12);  // STRAIGHT_FEED(0, 5, 1) after the G5.1
  EXPECT_NEAR(e[2][1], 5, 1e-12);
  EXPECT_NEAR(e[4][0], -5, 1e-12);  // STRAIGHT_FEED(-5, 0, 2) after the G5
  EXPECT_NEAR(e[4][1], 0, 1e-12);
  EXPECT_NEAR(e[6][0], 0, 1e-12);  // STRAIGHT_FEED(0, -5, 3): the current angle 180 + 90
  EXPECT_NEAR(e[6][1], -5, 1e-12);
}

TEST(IsoPolar, ProgramCoordinatesOfTheCurrentSystemWithRotationAndG92) {
  // rs274 prints program coordinates: (3, 4), (6, 8), then after G92 X1 Y1 (0, 1.4142), (0, 2.4142),
  // (2.4142, 0), (1.4142, 1.4142). softmc's machine point is rotate30(program + G92) + G54.
  const auto p = parse_ok(
      "G21 G90 G17 F100\nG10 L2 P1 X10 Y5 R30\nG0 X3 Y4\nG0 @10\nG92 X1 Y1\nG0 ^90\nG91 G0 @1\nG0 ^-90\n"
      "G90 G1 @2 ^45\n");
  const double c = std::cos(std::numbers::pi / 6), s = std::sin(std::numbers::pi / 6);
  auto machine = [&](double x, double y, double gx, double gy) {
    return std::vector<double>{(x + gx) * c - (y + gy) * s + 10, (x + gx) * s + (y + gy) * c + 5};
  };
  expect_ends(p, {machine(3, 4, 0, 0), machine(6, 8, 0, 0), machine(0, 1.4142, 5, 7), machine(0, 2.4142, 5, 7),
                  machine(2.4142, 0, 5, 7), machine(1.4142, 1.4142, 5, 7)});
}

TEST(IsoPolar, CutterCompensationTakesTheProgrammedPoint) {
  // rs274's compensated moves for the same program (G41.1 D4, a 2 mm radius on the left).
  const auto p = parse_ok(
      "G21 G90 G17 F300\nG0 X30 Y0 Z1\nG41.1 D4\nG1 @20 ^0\nG3 @20 ^90 I-20 J0\nG1 ^150\nG91 G1 @-5\nG1 ^30\n"
      "G90 G40 G0 @40\n");
  expect_ends(p, {{30, 0, 1},
                  {20, -2, 1},
                  {18, 0, 1},
                  {0.5227, 17.9924, 1},
                  {-13.3205, 10, 1},
                  {-11.9904, 9.2321, 1},
                  {-11.0585, 6.9824, 1},
                  {-13.0681, -0.5176, 1},
                  {-40, 0, 1}});
}

TEST(IsoPolar, ErrorsOfTheBlock) {
  // LinuxCNC: "Cannot specify both polar coordinate and X word" (and Y); softmc refuses a second @
  // as it refuses any repeated word (LinuxCNC keeps the last one silently).
  EXPECT_EQ(one_error("G0 X1\nG0 @5 X3\n"),
            "t.ngc:2:7: error: X word together with polar coordinates (@ ^): they give X and Y, use one or the other");
  EXPECT_EQ(one_error("G0 X1\nG0 Y2 ^5\n"),
            "t.ngc:2:4: error: Y word together with polar coordinates (@ ^): they give X and Y, use one or the other");
  EXPECT_EQ(one_error("G0 X10\nG0 @5 @6\n"), "t.ngc:2:7: error: two @ words in one block");
  EXPECT_EQ(one_error("G0 X1\nG0 @\n"), "t.ngc:2:4: error: @ word has no number");
}

TEST(IsoPolar, OnlyInTheG17PlaneAsLinuxCncChecksIt) {
  // "Cannot use polar coordinate except in G17 plane": LinuxCNC checks the plane in effect before the
  // block, so a G17 in the block comes too late; a block leaving G17 is refused as well.
  EXPECT_EQ(one_error("G18\nG0 @5 ^3\n"),
            "t.ngc:2:4: error: polar coordinates (@ ^) work only in the G17 plane, and G18 is in effect");
  EXPECT_EQ(one_error("G19\nG17 G0 @5 ^30\n"),
            "t.ngc:2:8: error: polar coordinates (@ ^) work only in the G17 plane, and G19 is in effect: select G17 "
            "on an earlier line");
  EXPECT_EQ(one_error("G18 G0 @5 ^30\n"),
            "t.ngc:1:8: error: polar coordinates (@ ^) work only in the G17 plane, and this block selects G18");
}

TEST(IsoPolar, OnlyForMotion) {
  // LinuxCNC: "Polar coordinates can only be used for motion", "Cannot use axis values with G80",
  // "Cannot use axis values without a g code that uses them", "Cannot use polar coordinates with G53".
  EXPECT_EQ(one_error("G92 @5\n"), "t.ngc:1:5: error: polar coordinates (@ ^) can only be used for motion, not with G92");
  EXPECT_EQ(one_error("G28 @5\n"), "t.ngc:1:5: error: polar coordinates (@ ^) can only be used for motion, not with G28");
  EXPECT_EQ(one_error("G10 L20 P1 @5\n"),
            "t.ngc:1:12: error: polar coordinates (@ ^) can only be used for motion, not with G10");
  EXPECT_EQ(one_error("G0 X1\nG43.1 Z1 @2\n"),
            "t.ngc:2:10: error: polar coordinates (@ ^) can only be used for motion, not with G43.1");
  EXPECT_EQ(one_error("G0 X1\nG28.1 ^2\n"),
            "t.ngc:2:7: error: polar coordinates (@ ^) can only be used for motion, not with G28.1");
  EXPECT_EQ(one_error("@5 ^3\n"), "t.ngc:1:1: error: polar coordinates (@ ^) with no motion mode: program G0, G1, G2 or G3 first");
  EXPECT_EQ(one_error("G80 @5 ^3\n"),
            "t.ngc:1:5: error: polar coordinates (@ ^) with G80: G80 cancels the motion mode and cannot move");
  EXPECT_EQ(one_error("G0 X1\nG53 G0 @5\n"), "t.ngc:2:1: error: G53 cannot be used with polar coordinates (@ ^)");
  // LinuxCNC's G5.2 reads X and Y only and would ignore them.
  EXPECT_EQ(one_error("G0 X10\nG5.2 @5 ^270 P1 L3 F100\n"),
            "t.ngc:2:6: error: polar coordinates (@ ^) cannot give a NURBS control point (G5.2): use X and Y");
  EXPECT_EQ(one_error("G0 X10\nG5.2 X10 Y0 P1 L3 F100\n@3 ^4 P1\nX3 Y4 P1\nG5.3\n"),
            "t.ngc:3:1: error: polar coordinates (@ ^) cannot give a NURBS control point (G5.2): use X and Y");
  EXPECT_EQ(one_error("G0 X10\nG5.2 X10 Y0 P1 L3 F100\nX1 Y2 P1\nX3 Y4 P1\nG5.3 @1\n"),
            "t.ngc:5:6: error: G5.3 takes no polar coordinates (@ ^)");
}

TEST(IsoPolar, TheAngleIsUndefinedAtTheOrigin) {
  // "Must specify angle in polar coordinate if at the origin"; "Incremental motion with polar
  // coordinates is indeterminate when at the origin" (G91 @) and "G91 motion … at the origin" (G91 ^).
  EXPECT_EQ(one_error("G0 X0 Y0\nG0 @5\n"),
            "t.ngc:2:4: error: polar radius (@) without an angle (^) at the origin: the current angle is undefined there");
  EXPECT_EQ(one_error("G91 G0 @5\n"),
            "t.ngc:1:8: error: incremental polar coordinates (G91 @) at the origin: the current angle is undefined there");
  EXPECT_EQ(one_error("G91 G0 ^5\n"),
            "t.ngc:1:8: error: incremental polar coordinates (G91 ^) at the origin: the current angle is undefined there");
  // The radius step may end on the origin: then the angle step has nothing to turn.
  EXPECT_EQ(one_error("G0 X3\nG91 G0 @-3 ^5\n"),
            "t.ngc:2:12: error: incremental polar coordinates (G91 ^) at the origin: the current angle is undefined there");
  // With both words in G90 the origin is fine, and so is ^ alone (radius 0).
  expect_ends(parse_ok("G0 @0 ^30\nG0 ^45\n"), {{0, 0, 0}, {0, 0, 0}});
}

TEST(IsoPolarCycles, G91AngleStepsDrillABoltHoleCircle) {
  // As LinuxCNC's hole-circle.ngc: six holes 60° apart on a 1.5 in radius about the origin. rs274:
  // up to R, then for each hole rapid over it at R, feed to Z-.4 and back to R.
  const auto p = parse_ok("G20 G17 G90 G98\nG0 X1.5 Y0 Z0\nG91 G81 R.1 Z-.5 ^60 L6 F10\n");
  const double holes[6][2] = {{0.75, 1.2990}, {-0.75, 1.2990}, {-1.5, 0}, {-0.75, -1.2990}, {0.75, -1.2990}, {1.5, 0}};
  std::vector<std::vector<double>> want = {{1.5, 0, 0}, {1.5, 0, 0.1}};
  for (const auto& h : holes) {
    want.push_back({h[0], h[1], 0.1});
    want.push_back({h[0], h[1], -0.4});
    want.push_back({h[0], h[1], 0.1});
  }
  expect_ends(p, want, 25.4);
}

TEST(IsoPolarCycles, G90HolesAreAtThePolarPointAndTheOriginGivesAngleZero) {
  // LinuxCNC's convert_cycle_xy takes atan2(0, 0) = 0 for @ alone at the origin (a straight move
  // refuses it); ^ alone keeps the current radius. G91 @0 ^0 are no steps at all, also at the origin.
  // G91 @ and ^ together step every repeat: the radius, then the angle.
  const auto p = parse_ok(
      "G21 G90 G17 G98\nG0 X0 Y0 Z5\nG81 @7 R1 Z-2 F100\nG81 ^90\nG80\nG0 X0 Y0\nG91 G81 @0 ^0 R1 Z-2\nG80\n"
      "G90 G0 X1 Y1\nG91 G99 G81 @2 ^45 R-3 Z-2 L4\n");
  expect_ends(p, {{0, 0, 5},          {7, 0, 5},          {7, 0, 1},          {7, 0, -2},        {7, 0, 5},
                  {0, 7, 5},          {0, 7, 1},          {0, 7, -2},         {0, 7, 5},         {0, 0, 5},
                  {0, 0, 6},          {0, 0, 6},          {0, 0, 4},          {0, 0, 6},         {1, 1, 6},
                  {0, 3.4142, 6},     {0, 3.4142, 3},     {0, 3.4142, 1},     {0, 3.4142, 3},    {-3.8284, 3.8284, 3},
                  {-3.8284, 3.8284, 1}, {-3.8284, 3.8284, 3}, {-7.4142, 0, 3}, {-7.4142, 0, 1}, {-7.4142, 0, 3},
                  {-6.6569, -6.6569, 3}, {-6.6569, -6.6569, 1}, {-6.6569, -6.6569, 3}});
}

TEST(IsoPolarCycles, G91RepeatsThatReachTheOriginStop) {
  // rs274 drills (1, 0) and (0, 0), then stops: "Incremental motion with polar coordinates is
  // indeterminate when at the origin". softmc refuses the whole block.
  EXPECT_EQ(one_error("G21 G90 G17\nG0 X2 Y0 Z5\nG91 G98 G81 @-1 R1 Z-2 L3 F100\n"),
            "t.ngc:3:13: error: incremental polar coordinates (G91 @) at the origin in repeat 3 of the canned cycle: "
            "the current angle is undefined there");
  EXPECT_EQ(one_error("G21 G90 G17\nG0 X0 Y0 Z5\nG91 G98 G81 ^60 R1 Z-2 L2 F100\n"),
            "t.ngc:3:13: error: incremental polar coordinates (G91 ^) at the origin in repeat 1 of the canned cycle: "
            "the current angle is undefined there");
  EXPECT_EQ(one_error("G0 X1 Z5\nG91 G81 X1 @1 R1 Z-2 F100\n"),
            "t.ngc:2:9: error: X word together with polar coordinates (@ ^): they give X and Y, use one or the other");
  EXPECT_EQ(one_error("G18 G0 X1 Z5\nG81 @1 R1 Y-2 F100\n"),
            "t.ngc:2:5: error: polar coordinates (@ ^) work only in the G17 plane, and G18 is in effect");
}
