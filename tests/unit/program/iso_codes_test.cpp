// ISO G and M codes: planes, R arcs, offsets (G10/G54…/G92/G28/G43), canned cycles, splines, path
// control, feed modes, M functions of plc_interface.md P-10, cutter compensation routing.
#include <gtest/gtest.h>

#include <cmath>

#include <fmt/format.h>

#include "iso_test_util.hpp"
#include "program/iso/m_functions.hpp"
#include "program/iso/tool_table.hpp"

using namespace softmc;
using namespace softmc::program;
using namespace softmc::program::iso::test;

namespace {


template <class T>
std::vector<T> all(const Program& p) {
  std::vector<T> out;
  for (const auto& i : p.instructions)
    if (const auto* x = op_if<T>(i.op)) out.push_back(*x);
  return out;
}

}  // namespace

TEST(IsoArcs, RadiusFormatSignSelectsTheShortOrLongArc) {
  // From (0,0) to (10,0), R10: the short G2 arc has its centre below, R-10 above (LinuxCNC arc_data_r).
  const auto a = all<Arc>(parse_ok("G2 X10 Y0 R10 F60\n"));
  ASSERT_EQ(a.size(), 1u);
  EXPECT_NEAR(a[0].center0, 5, 1e-12);
  EXPECT_NEAR(a[0].center1, -10 * std::cos(std::asin(0.5)), 1e-12);
  const auto b = all<Arc>(parse_ok("G2 X10 Y0 R-10 F60\n"));
  EXPECT_NEAR(b[0].center1, 10 * std::cos(std::asin(0.5)), 1e-12);
  const auto c = all<Arc>(parse_ok("G3 X10 Y0 R10 F60\n"));
  EXPECT_NEAR(c[0].center1, 10 * std::cos(std::asin(0.5)), 1e-12);
  const auto half = all<Arc>(parse_ok("G3 X10 Y0 R5 F60\n"));  // a semicircle
  EXPECT_NEAR(half[0].center0, 5, 1e-12);
  EXPECT_NEAR(half[0].center1, 0, 1e-9);
}

TEST(IsoArcs, RadiusFormatErrors) {
  EXPECT_EQ(one_error("G2 X10 Y0 R4 F60\n"),
            "t.ngc:1:1: error: arc radius 4.0000 mm is too small to reach the end point (10.0000 mm away)");
  EXPECT_EQ(one_error("G0 X1\nG2 X1 Y0 R4 F60\n"),
            "t.ngc:2:1: error: R-format arc with the end point equal to the start point: a full circle needs I/J/K");
  EXPECT_EQ(one_error("G2 X1 R4 I1 F60\n"),
            "t.ngc:1:7: error: R word together with centre words: give the arc either a radius or a centre");
}

TEST(IsoArcs, RadiusFormatAllowsARadiusJustShortOfHalfTheChord) {
  // LinuxCNC 2.9 arc_data_r refuses only when half the chord exceeds |R| by more than
  // RADIUS_TOLERANCE (0.00005 in = 0.00127 mm); up to that it makes a half circle. rs274 -g:
  // "G3 X20 Y0 R9.999" from (0, 0) is ARC_FEED(20, 0, 10, 0, 1, ..), "G2 X0 Y0 R-9.9988" back
  // ARC_FEED(0, 0, 10, -0, -1, ..), "G3 X20 Y0 R9.9987" is "Arc radius too small to reach end point",
  // and in G20 "G3 X2 Y0 R0.99996" is ARC_FEED(2, 0, 1, 0, 1, ..).
  const auto a = all<Arc>(parse_ok("G3 X20 Y0 R9.999 F60\nG2 X0 Y0 R-9.9988\n"));
  ASSERT_EQ(a.size(), 2u);
  EXPECT_NEAR(a[0].center0, 10, 1e-9);
  EXPECT_NEAR(a[0].center1, 0, 1e-9);
  EXPECT_EQ(a[0].turns, 1);
  EXPECT_NEAR(a[1].center0, 10, 1e-9);
  EXPECT_NEAR(a[1].center1, 0, 1e-9);
  EXPECT_EQ(a[1].turns, -1);
  EXPECT_EQ(one_error("G3 X20 Y0 R9.9987 F60\n"),
            "t.ngc:1:1: error: arc radius 9.9987 mm is too small to reach the end point (20.0000 mm away)");
  const auto inch = all<Arc>(parse_ok("G20 G3 X2 Y0 R0.99996 F60\n"));
  ASSERT_EQ(inch.size(), 1u);
  EXPECT_NEAR(inch[0].center0, 25.4, 1e-9);
  EXPECT_NEAR(inch[0].center1, 0, 1e-9);
}

TEST(IsoArcs, PlanesG18AndG19WithHelix) {
  // G18: arc in (Z, X), normal Y; centre words K (Z) and I (X).
  const auto a = all<Arc>(parse_ok("G0 X10 Z0\nG18 G3 X0 Z10 Y5 I-10 K0 F60\n"));
  ASSERT_EQ(a.size(), 1u);
  EXPECT_EQ(a[0].axis0, 2);
  EXPECT_EQ(a[0].axis1, 0);
  EXPECT_EQ(a[0].normal, 1);
  EXPECT_NEAR(a[0].center0, 0, 1e-12);
  EXPECT_NEAR(a[0].center1, 0, 1e-12);
  EXPECT_EQ(a[0].end[1], 5);  // the helix axis moves linearly
  const auto b = all<Arc>(parse_ok("G0 Y10\nG19 G2 Y0 Z-10 J-10 F60\n"));
  EXPECT_EQ(b[0].axis0, 1);
  EXPECT_EQ(b[0].axis1, 2);
  EXPECT_EQ(b[0].turns, -1);
  EXPECT_EQ(one_error("G18 G2 X1 J1 F60\n"), "t.ngc:1:11: error: J word in a G18 arc: the centre is given by K and I");
}

TEST(IsoArcs, RotaryAxesInDegreesAreNotScaledByG20) {
  const auto p = parse_ok("G20 G0 X1 A90 C-45\n");
  EXPECT_DOUBLE_EQ(ends(p)[0][0], 25.4);
  EXPECT_DOUBLE_EQ(ends(p)[0][3], 90);
  EXPECT_DOUBLE_EQ(ends(p)[0][5], -45);
}

TEST(IsoOffsets, WorkOffsetsG10L2AndG54ToG59_3) {
  const auto p = parse_ok("G10 L2 P1 X10 Y20\nG10 L2 P2 X-5\nG10 L2 P9 Z3\nG0 X0 Y0\nG55 X0 Y0\nG59.3 X1 Z0\nG54 X0\n");
  const auto e = ends(p);
  ASSERT_EQ(e.size(), 4u);
  EXPECT_EQ(e[0], xyz(10, 20));
  EXPECT_EQ(e[1], xyz(-5, 0));
  EXPECT_EQ(e[2], xyz(1, 0, 3));
  EXPECT_EQ(e[3], xyz(10, 0, 3));
  const auto o = all<OffsetsChanged>(p);
  ASSERT_FALSE(o.empty());
  EXPECT_EQ(o.back().coord_system, 1);
}

TEST(IsoOffsets, G10L20MakesTheCurrentPositionTheGivenCoordinate) {
  const auto p = parse_ok("G0 X30 Y40\nG10 L20 P1 X0 Y0\nG0 X5 Y5\nG0 X#5221 Y#5222\n");
  const auto e = ends(p);
  EXPECT_EQ(e[1], xyz(35, 45));
  EXPECT_EQ(e[2], xyz(60, 80));  // #5221 = 30, in G54 → machine 60
}

TEST(IsoOffsets, G10L20OnARotatedCoordinateSystem) {
  // LinuxCNC 2.9 convert_setup: in a rotated system X and Y are found together, the one not given
  // keeping its current coordinate there; G92 counts as in every move. rs274 -g prints
  // SET_G5X_OFFSET(2, 13.4641, 22.0000, ..), (2, 10.4641, 27.1962, ..), (2, 10.6962, 30.7942, ..)
  // and (2, -1.4641, -5.4641, ..) for the four L20 below (G55 rotated 30°).
  const auto p = parse_ok(
      "G10 L2 P2 X10 Y20 R30\nG55 G0 X5 Y7\nG10 L20 P2 X1\nG0 X3 Y4\nG10 L20 P0 Y-2\nG0 X6 Y6\nG92 X1 Y1\n"
      "G0 X2 Y3\nG10 L20 P2 X0 Y0\nG0 X1 Y1\nG92.1\nG54 G0 X0 Y0\nG10 L20 P2 X4 Y4\nG55 G0 X0 Y0\n");
  std::vector<std::pair<double, double>> g55;
  for (const auto& o : all<OffsetsChanged>(p))
    if (o.coord_system == 2) g55.emplace_back(o.work[0], o.work[1]);
  const std::vector<std::pair<double, double>> want = {
      {10, 20}, {13.4641, 22.0}, {10.4641, 27.1962}, {10.6962, 30.7942}, {-1.4641, -5.4641}};
  ASSERT_GE(g55.size(), want.size());
  std::vector<std::pair<double, double>> distinct;  // G92 and the G55 select repeat the same offsets
  for (const auto& w : g55)
    if (distinct.empty() || std::fabs(distinct.back().first - w.first) + std::fabs(distinct.back().second - w.second) > 1e-9)
      distinct.push_back(w);
  ASSERT_EQ(distinct.size(), want.size());
  for (std::size_t i = 0; i < want.size(); ++i) {
    EXPECT_NEAR(distinct[i].first, want[i].first, 1e-4) << i;
    EXPECT_NEAR(distinct[i].second, want[i].second, 1e-4) << i;
  }
}

TEST(IsoOffsets, CoordinateSystemRotation) {
  const auto p = parse_ok("G10 L2 P1 X10 R90\nG0 X5 Y0\n");
  EXPECT_NEAR(ends(p)[0][0], 10, 1e-12);
  EXPECT_NEAR(ends(p)[0][1], 5, 1e-12);
}

TEST(IsoOffsets, G92FamilyAsLinuxCnc) {
  const auto p = parse_ok(
      "G0 X10 Y3\nG92 X0\nG0 X5\n"  // X5 is machine 15
      "G0 X#5211\n"                  // #5211 = 10 → machine 20
      "G92.2\nG0 X5\n"               // offsets off, parameters kept
      "G92.3\nG0 X5\n"               // restored
      "G92.1\nG0 X5\nG0 X#5211\n");  // off and cleared
  const auto e = ends(p);
  ASSERT_EQ(e.size(), 7u);
  EXPECT_EQ(e[1][0], 15);
  EXPECT_EQ(e[2][0], 20);
  EXPECT_EQ(e[3][0], 5);
  EXPECT_EQ(e[4][0], 15);
  EXPECT_EQ(e[5][0], 5);
  EXPECT_EQ(e[6][0], 0);
  EXPECT_EQ(e[1][1], 3);  // Y untouched
}

TEST(IsoOffsets, G28AndG30StoredPositions) {
  const auto p = parse_ok("G0 X1 Y2 Z3\nG28.1\nG0 X50 Y50 Z50\nG28\nG0 X9 Y9 Z9\nG28 Z20\n#5181 = 7\nG30 X0\n");
  const auto e = ends(p);
  ASSERT_EQ(e.size(), 8u);
  EXPECT_EQ(e[2], xyz(1, 2, 3));     // G28: every axis home
  EXPECT_EQ(e[4], xyz(9, 9, 20));    // G28 Z20: via Z20 …
  EXPECT_EQ(e[5], xyz(9, 9, 3));     // … then only Z home
  EXPECT_EQ(e[6], xyz(0, 9, 3));     // G30 X0: via X0 …
  EXPECT_EQ(e[7], xyz(7, 9, 3));     // … then X to #5181
}

TEST(IsoOffsets, G53MovesInMachineCoordinates) {
  const auto p = parse_ok("G10 L2 P1 X100\nG0 X1\nG53 G0 X1\nG1 G53 X2 F60\n");
  const auto e = ends(p);
  EXPECT_EQ(e[0][0], 101);
  EXPECT_EQ(e[1][0], 1);
  EXPECT_EQ(e[2][0], 2);
  EXPECT_EQ(one_error("G91 G53 G0 X1\n"), "t.ngc:1:5: error: G53 cannot be used in incremental mode (G91)");
  EXPECT_EQ(one_error("G53 G2 X1 I1 F60\n"), "t.ngc:1:1: error: G53 needs G0 or G1 in effect: it moves in machine coordinates");
}

TEST(IsoOffsets, ToolParametersAreTheLoadedToolsTableEntry) {
  // LinuxCNC set_tool_parameters: #5400 the loaded tool, #5401…#5409 its table offsets, #5410 its
  // diameter, from M6/M61 on and whatever G43/G49 says. rs274 -g with this table (numbers as
  // written): " a 1.000000 1.000000 0.062500" after T1 M6 before any G43, " g 2.000000 0.500000
  // 0.250000" after T2 M6 G43 and G49.
  const auto tt = tools_ok("T1 P1 Z1.0 D0.0625\nT2 P2 Z0.5 D0.25\n");
  iso::ParseOptions opt;
  opt.tools = &tt;
  const auto p = parse_ok("(DEBUG, z #5400 #5403 #5410)\nT1 M6\n(DEBUG, a #5400 #5403 #5410)\nG43\n(DEBUG, b #5403)\n"
                          "T2 M6 G43\nG49\n(DEBUG, g #5400 #5403 #5410)\n",
                          opt);
  const auto texts = messages(p);
  const std::vector<std::string> want = {" z 0.000000 0.000000 0.000000", " a 1.000000 1.000000 0.062500", " b 1.000000",
                                         " g 2.000000 0.500000 0.250000"};
  EXPECT_EQ(texts, want);
}

TEST(IsoOffsets, ToolLengthFromTheToolTable) {
  const auto tt = tools_ok("T1 P1 D6 Z25 ; end mill\nT2 D1.5 Z-2\n");
  iso::ParseOptions opt;
  opt.tools = &tt;
  const auto r = iso::parse("G43 H1\nG0 Z0\nT2 M6\nG43\nG0 Z0\nG43.1 Z4\nG0 Z0\nG49\nG0 Z0\nG43 H7\n", "t.ngc", opt);
  const auto e = formatted(r);
  ASSERT_EQ(e, std::vector<std::string>{"t.ngc:10:5: error: tool 7 is not in the tool table"});
  const auto p = parse_ok("G43 H1\nG0 Z0\nT2 M6\nG43\nG0 Z0\nG43.1 Z4\nG0 Z0\nG49\nG0 Z0\n", opt);
  const auto z = ends(p);
  ASSERT_EQ(z.size(), 4u);
  EXPECT_EQ(z[0][2], 25);
  EXPECT_EQ(z[1][2], -2);
  EXPECT_EQ(z[2][2], 4);
  EXPECT_EQ(z[3][2], 0);
  EXPECT_EQ(all<ToolChange>(p).at(0).tool, 2);
}

TEST(IsoOffsets, ToolTableErrorsHaveLineAndColumn) {
  core::Diagnostics d;
  iso::parse_tool_table("T1 D6\nP2 D3\nT3 D-1\nT4 K1\n", "tools.tbl", d);
  ASSERT_EQ(d.size(), 3u);
  EXPECT_EQ(d[0].format(), "tools.tbl:2:1: error: tool table line without a T word");
  EXPECT_EQ(d[1].format(), "tools.tbl:3:4: error: tool diameter must be 0 or more");
  EXPECT_EQ(d[2].format(), "tools.tbl:4:4: error: unknown tool table word K");
}

TEST(IsoCannedCycles, G80WithAnotherMotionCodeInTheBlockIsIgnored) {
  // LinuxCNC read_g allows G80 on the same line as one other motion code and ignores it (CAM safety
  // lines "G0 G17 G40 G49 G80 G90"). rs274 -g on this program: STRAIGHT_TRAVERSE to Z5 and Z10,
  // STRAIGHT_FEED to Z3, the G81 at (0, 0) and (1, 0) from R2 to Z-1, then STRAIGHT_TRAVERSE(0, 0, 2).
  const auto p = parse_ok("G0 X0 Y0 Z5\nG80 G0 Z10\nG1 G80 Z3 F60\nG99 G81 G80 Z-1 R2\nG80 G81 X1\n"
                          "G0 G80 G17 G40 G49 G90 X0\n");
  const std::vector<core::Vec> want = {xyz(0, 0, 5),  xyz(0, 0, 10), xyz(0, 0, 3), xyz(0, 0, 3),
                                       xyz(0, 0, 2),  xyz(0, 0, -1), xyz(0, 0, 2), xyz(1, 0, 2),
                                       xyz(1, 0, -1), xyz(1, 0, 2),  xyz(0, 0, 2)};
  EXPECT_EQ(ends(p), want);
  EXPECT_TRUE(std::holds_alternative<Rapid>(p.instructions[1].op));
  EXPECT_TRUE(std::holds_alternative<Linear>(p.instructions[2].op));
  // A repeated G80 is ignored too (rs274 -g: the feed to X5 below).
  const auto g = parse_ok("G80 G80 G1 X5 F60\nG80 G80\n");
  EXPECT_EQ(ends(g), std::vector<core::Vec>{xyz(5, 0, 0)});
  // Two motion codes besides G80 are still two.
  EXPECT_EQ(one_error("G80 G0 G1 X1 F60\n"), "t.ngc:1:8: error: two motion codes in one block: G0 and G1");
}

TEST(IsoCannedCycles, RetractModeStartsAsG99) {
  // LinuxCNC's interpreter starts in R_PLANE retract mode (G99; #<_retract_r_plane> is 1 at start).
  // rs274 -g of "G0 X0 Y0 Z10 / G81 X5 Y5 Z-2 R1 F60 / X15" retracts to R: STRAIGHT_TRAVERSE(5, 5, 10),
  // (5, 5, 1), STRAIGHT_FEED(5, 5, -2), STRAIGHT_TRAVERSE(5, 5, 1), (15, 5, 1), STRAIGHT_FEED(15, 5, -2),
  // STRAIGHT_TRAVERSE(15, 5, 1).
  const auto p = parse_ok("G0 X0 Y0 Z10\nG81 X5 Y5 Z-2 R1 F60\nX15\n");
  const std::vector<core::Vec> want = {xyz(0, 0, 10), xyz(5, 5, 10), xyz(5, 5, 1), xyz(5, 5, -2), xyz(5, 5, 1),
                                       xyz(15, 5, 1), xyz(15, 5, -2), xyz(15, 5, 1)};
  EXPECT_EQ(ends(p), want);
}

TEST(IsoCannedCycles, G81DrillWithG98AndG99) {
  const auto p = parse_ok("G0 X0 Y0 Z10\nG98 G81 X5 Y5 Z-2 R1 F60\nX15\nG99 X25\nG80\n");
  const auto e = ends(p);
  const std::vector<core::Vec> want = {xyz(0, 0, 10),
                                       xyz(5, 5, 10), xyz(5, 5, 1), xyz(5, 5, -2), xyz(5, 5, 10),
                                       xyz(15, 5, 10), xyz(15, 5, 1), xyz(15, 5, -2), xyz(15, 5, 10),
                                       xyz(25, 5, 10), xyz(25, 5, 1), xyz(25, 5, -2), xyz(25, 5, 1)};
  EXPECT_EQ(e, want);
  EXPECT_TRUE(std::holds_alternative<Linear>(p.instructions[4].op));  // the drilling move feeds (after G61)
}

TEST(IsoCannedCycles, CyclesRunInExactPathModeAndRestoreTheModeAfter) {
  // LinuxCNC convert_cycle_*: after the rise to R, SET_MOTION_CONTROL_MODE(CANON_EXACT_PATH), the
  // cycle, then the saved mode again; nothing when G61 is already in effect. rs274 -g for
  // "G64 P0.5 / G0 X0 Y0 Z0 / G81 X10 Y10 Z-5 R2 / G61.1 / G81 X20 .. / G61 / G81 X30 ..":
  // TRAVERSE(0, 0, 2), EXACT_PATH, the cycle, CONTINUOUS 0.5; EXACT_STOP, the rise to R (from the
  // run's initial level Z0: a move of length 0), EXACT_PATH, the cycle, EXACT_STOP; EXACT_PATH (G61),
  // the rise and the cycle with no switch.
  const auto p = parse_ok("G64 P0.5\nG0 X0 Y0 Z0\nG81 X10 Y10 Z-5 R2 F60\nG61.1\nG81 X20 Y10 Z-5 R2\nG61\nG81 X30 Z-5 R2\n");
  std::vector<std::string> seq;
  for (const auto& ins : p.instructions) {
    if (const auto* m = std::get_if<PathMode>(&ins.op))
      seq.push_back(m->kind == PathKind::ExactPath ? "G61" : m->kind == PathKind::ExactStop ? "G61.1" : fmt::format("G64 P{:g}", m->tolerance_mm));
    else if (const auto* r = std::get_if<Rapid>(&ins.op)) seq.push_back(fmt::format("rapid z{:g}", r->end[2]));
    else if (std::holds_alternative<Linear>(ins.op)) seq.push_back("feed");
  }
  const std::vector<std::string> want = {
      "G64 P0.5", "rapid z0", "rapid z2", "G61", "rapid z2", "feed", "rapid z2", "G64 P0.5",  // line 3
      "G61.1", "rapid z2", "G61", "rapid z2", "feed", "rapid z2", "G61.1",                    // lines 4-5
      "G61", "rapid z2", "rapid z2", "feed", "rapid z2"};                                     // lines 6-7
  EXPECT_EQ(seq, want);
  // With no path mode named, the cycle goes back to the machine's default: a blend without P.
  const auto q = parse_ok("G0 Z5\nG81 X1 Z-1 R1 F60\n");
  const auto& back = std::get<PathMode>(q.instructions.back().op);
  EXPECT_EQ(back.kind, PathKind::Blend);
  EXPECT_EQ(back.tolerance_mm, 0);
}

TEST(IsoCannedCycles, G83PeckAndG73ChipBreak) {
  const auto p = parse_ok("G0 Z10\nG98 G83 X0 Y0 Z-3 R1 Q1.5 F60\n");
  std::vector<double> z;
  for (const auto& v : ends(p)) z.push_back(v[2]);
  // G83 clears chips at R between pecks (rs274: cycle_g83 traverses to r), and retracts to the
  // initial level (G98) only at the end.
  const std::vector<double> want = {10, 10, 1, -0.5, 1, -0.5 + 0.254, -2, 1, -2 + 0.254, -3, 10};
  ASSERT_EQ(z.size(), want.size());
  for (std::size_t i = 0; i < z.size(); ++i) EXPECT_NEAR(z[i], want[i], 1e-12) << i;
  const auto q = parse_ok("G0 Z10\nG99 G73 X0 Y0 Z-3 R1 Q2 F60\n");
  std::vector<double> z73;
  for (const auto& v : ends(q)) z73.push_back(v[2]);
  const std::vector<double> want73 = {10, 10, 1, -1, -1 + 0.254, -3, 1};
  ASSERT_EQ(z73.size(), want73.size());
  for (std::size_t i = 0; i < z73.size(); ++i) EXPECT_NEAR(z73[i], want73[i], 1e-12) << i;
}

TEST(IsoCannedCycles, G98AfterG99ReturnsToTheInitialLevel) {
  // The golden drilling program's case: the initial level (Z10) is kept across consecutive cycles,
  // so a G98 cycle after G99 ones rises back to it; G80 ends the run.
  const auto p = parse_ok("G0 Z10\nG99 G81 X0 Y0 Z-1 R2 F60\nG98 G81 X5 Z-1 R2\nG80\nG0 Z4\nG98 G81 X9 Z-1 R2\n");
  std::vector<double> z;
  for (const auto& v : ends(p)) z.push_back(v[2]);
  const std::vector<double> want = {10, 10, 2, -1, 2, 10, 2, -1, 10, 4, 4, 2, -1, 4};
  ASSERT_EQ(z.size(), want.size());
  for (std::size_t i = 0; i < z.size(); ++i) EXPECT_NEAR(z[i], want[i], 1e-12) << i;
}

TEST(IsoCannedCycles, IncrementalRepeatsAndDwell) {
  // G91: X/Y increments per repeat, R from the initial Z, Z from R (LinuxCNC).
  const auto p = parse_ok("G0 X0 Y0 Z5\nG98 G91 G82 X10 Y0 Z-4 R-3 P0.5 L3 F60\n");
  const auto e = ends(p);
  ASSERT_EQ(e.size(), 1u + 3 * 4);
  EXPECT_EQ(e[1], xyz(10, 0, 5));
  EXPECT_EQ(e[2], xyz(10, 0, 2));
  EXPECT_EQ(e[3], xyz(10, 0, -2));
  EXPECT_EQ(e[12], xyz(30, 0, 5));
  EXPECT_EQ(all<Dwell>(p).size(), 3u);
}

TEST(IsoCannedCycles, Errors) {
  EXPECT_EQ(one_error("G81 X1 Y1 R1 F60\n"), "t.ngc:1:1: error: Z word missing: the canned cycle needs the bottom of the hole");
  EXPECT_EQ(one_error("G81 X1 Z-1 F60\n"), "t.ngc:1:1: error: R word missing: the canned cycle needs the retract plane");
  EXPECT_EQ(one_error("G0 Z5\nG81 X1 Z2 R1 F60\n"),
            "t.ngc:2:1: error: the retract plane R is below the bottom of the hole Z (1.0000 < 2.0000)");
  EXPECT_EQ(one_error("G83 X1 Z-1 R1 F60\n"), "t.ngc:1:1: error: Q word missing: the peck cycle needs the peck depth");
  EXPECT_EQ(one_error("G81 X1 Z-1 R1\n"), "t.ngc:1:1: error: feed rate missing: program an F word before the first feed move");
}

TEST(IsoSplines, G5CubicContinuesAndG5_1Quadratic) {
  const auto p = parse_ok("G5 X10 Y0 I2 J2 P-2 Q2 F60\nG5 X20 Y0 P-2 Q-2\nG5.1 X30 Y0 I5 J5\n");
  const auto b = all<Bezier>(p);
  ASSERT_EQ(b.size(), 3u);
  EXPECT_EQ(b[0].degree, 3);
  EXPECT_EQ(b[0].ctrl1, xyz(2, 2));
  EXPECT_EQ(b[0].ctrl2, xyz(8, 2));
  EXPECT_EQ(b[1].ctrl1, xyz(12, -2));  // I J = -(previous P Q): a smooth joint
  EXPECT_EQ(b[2].degree, 2);
  EXPECT_EQ(b[2].ctrl1, xyz(25, 5));
  EXPECT_EQ(one_error("G5 X10 P1 Q1 F60\n"), "t.ngc:1:1: error: G5 needs I and J: only a G5 right after a G5 may leave them out");
  EXPECT_EQ(one_error("G18 G5 X10 I1 J1 P1 Q1 F60\n"), "t.ngc:1:5: error: G5 only works in the XY plane (G17)");
}

TEST(IsoSplines, G5_2NurbsBlock) {
  const auto p = parse_ok("G0 X0 Y0\nF60\nG5.2 X0 Y10 P1 L3\nX10 Y10 P2\nX10 Y0 P1\nG5.3\nG1 X0\n");
  const auto n = all<Nurbs>(p);
  ASSERT_EQ(n.size(), 1u);
  EXPECT_EQ(n[0].order, 3);
  ASSERT_EQ(n[0].ctrl.size(), 4u);
  EXPECT_EQ(n[0].ctrl[0], xyz(0, 0));
  EXPECT_EQ(n[0].ctrl[2], xyz(10, 10));
  EXPECT_EQ(n[0].weights, (std::vector<double>{1, 1, 2, 1}));
  EXPECT_EQ(parse_errors("F60\nG5.2 X1 Y1\nG5.3\n").at(0),
            "t.ngc:3:1: error: a NURBS of order 3 needs at least 3 control points (the start point counts), it has 2");
  EXPECT_EQ(one_error("G5.3\n"), "t.ngc:1:1: error: G5.3 without an open G5.2 block");
}

TEST(Iso, P12_PathControlG61G64AndG23) {
  iso::ParseOptions opt;
  opt.g23_tolerance_mm = 0.1;
  const auto p = parse_ok("G64 P0.05 Q0.02\nG61.1\nG61\nG23\nG20 G64 P0.001\n", opt);
  const auto m = all<PathMode>(p);
  ASSERT_EQ(m.size(), 5u);
  EXPECT_EQ(m[0].kind, PathKind::Blend);
  EXPECT_DOUBLE_EQ(m[0].tolerance_mm, 0.05);
  EXPECT_DOUBLE_EQ(m[0].naive_tolerance_mm, 0.02);
  EXPECT_EQ(m[1].kind, PathKind::ExactStop);
  EXPECT_EQ(m[2].kind, PathKind::ExactPath);
  EXPECT_TRUE(m[3].continuous);  // G23: continuous path with the configured tolerance
  EXPECT_DOUBLE_EQ(m[3].tolerance_mm, 0.1);
  EXPECT_DOUBLE_EQ(m[4].tolerance_mm, 0.0254);
  EXPECT_EQ(one_error("G64 Q1\n"), "t.ngc:1:5: error: G64 Q needs a P word as well");
}

TEST(IsoFeed, InverseTimeG93) {
  // G93 F2: the move takes 1/2 minute = 30 s; 30 mm long → 1 mm/s.
  const auto p = parse_ok("G93 G1 X30 F2\n");
  EXPECT_DOUBLE_EQ(op_at<Linear>(p, 0).feed_mm_s, 1.0);
  EXPECT_EQ(one_error("G93 G1 X30 F2\nX40\n"), "t.ngc:2:1: error: inverse time feed (G93): every feed move needs its own F word");
  EXPECT_EQ(one_error("G95 G1 X1 F1\n"), "t.ngc:1:1: error: G95 (feed per revolution) is not supported: the machine has no spindle feedback");
}

TEST(IsoSpindle, SpeedAndConstantSurfaceSpeed) {
  const auto p = parse_ok("S1200 M3\nG96 S200 D3000\nG97 S500\n");
  const auto s = all<SpindleSpeed>(p);
  ASSERT_EQ(s.size(), 3u);
  EXPECT_DOUBLE_EQ(s[0].rpm, 1200);
  EXPECT_TRUE(s[1].css);
  EXPECT_DOUBLE_EQ(s[1].surface_m_min, 200);
  EXPECT_DOUBLE_EQ(s[1].max_rpm, 3000);
  EXPECT_FALSE(s[2].css);
}

TEST(Iso, P10_MGroupsAndChangeBits) {
  const iso::MTable mt;
  EXPECT_EQ(mt.get(30).group, 1);
  EXPECT_EQ(mt.get(19).group, 2);
  EXPECT_EQ(mt.get(42).group, 3);
  EXPECT_EQ(mt.get(17).group, 5);
  EXPECT_EQ(mt.get(52).group, 6);
  EXPECT_EQ(mt.get(11).group, 7);
  EXPECT_EQ(mt.get(49).group, 8);
  EXPECT_EQ(mt.get(60).group, 9);
  EXPECT_EQ(mt.get(77).group, 14);  // everything else
  iso::MGroupState s;
  s.begin_block();
  s.apply(3, mt);
  s.apply(8, mt);
  s.apply(41, mt);
  EXPECT_TRUE(s.m3);
  EXPECT_FALSE(s.coolant1);
  EXPECT_TRUE(s.coolant2);  // M08 → 01
  EXPECT_EQ(s.gear, 1);
  EXPECT_TRUE(s.changed[2] && s.changed[5] && s.changed[3]);
  EXPECT_FALSE(s.changed[1]);
  s.begin_block();
  EXPECT_FALSE(s.changed[2]);  // change bits last one block …
  EXPECT_EQ(s.value[2], 3);    // … values stay
  s.apply(3, mt);
  EXPECT_TRUE(s.changed[2]);  // the same value programmed again still sets the change bit
  s.apply(17, mt);
  EXPECT_TRUE(s.coolant1 && s.coolant2);  // M17 → 11
  s.apply(5, mt);
  EXPECT_FALSE(s.m3 || s.m4 || s.m19);
  s.apply(52, mt);
  EXPECT_TRUE(s.m50_1 && s.m50_2);
  s.apply(6, mt);
  EXPECT_TRUE(s.m6);
  s.begin_block();
  EXPECT_FALSE(s.m6);  // dynamic bits last one block
  s.apply(49, mt);
  EXPECT_FALSE(s.feed_override_enabled);
}

TEST(Iso, P10_UserMFunctionsAndTheirGroupsInTheIr) {
  iso::MTable mt;
  EXPECT_TRUE(mt.configure(iso::MConfig{90, 10, true, false, false}));
  EXPECT_TRUE(mt.configure(iso::MConfig{91, 10}));
  EXPECT_FALSE(mt.configure(iso::MConfig{3, 10}));  // fixed functions keep their group
  EXPECT_TRUE(mt.configure(iso::MConfig{3, 2, true}));  // but their flags may change
  EXPECT_FALSE(mt.configure(iso::MConfig{92, 2}));  // a user function may not join a fixed group
  iso::ParseOptions opt;
  opt.m_table = &mt;
  const auto p = parse_ok("M90 M7 M8\nM91\n", opt);
  const auto m = all<MFunction>(p);
  ASSERT_EQ(m.size(), 4u);
  for (const auto& f : m) EXPECT_EQ(f.group, f.number == 90 || f.number == 91 ? 10 : 5) << f.number;
  EXPECT_EQ(parse_errors("M90 M91\n", opt), std::vector<std::string>{"t.ngc:1:5: error: two M codes of group 10 in one block: M90 and M91"});
  EXPECT_EQ(parse_errors("M7 M9\n"), std::vector<std::string>{"t.ngc:1:4: error: two M codes of group 5 in one block: M7 and M9"});
}

TEST(Iso, P10_StopsToolChangeAndIo) {
  const auto p = parse_ok("T3 M6\nM0\nM1\nM62 P2\nM65 P4\nM60\n");
  EXPECT_EQ(all<ToolSelect>(p).at(0).tool, 3);
  EXPECT_EQ(all<ToolChange>(p).at(0).tool, 3);
  const auto pauses = all<Pause>(p);
  ASSERT_EQ(pauses.size(), 3u);
  EXPECT_FALSE(pauses[0].optional);
  EXPECT_TRUE(pauses[1].optional);
  const auto d = all<DigitalOutput>(p);
  ASSERT_EQ(d.size(), 2u);
  EXPECT_TRUE(d[0].on && d[0].synced);
  EXPECT_EQ(d[1].index, 4);
  EXPECT_FALSE(d[1].on || d[1].synced);
  EXPECT_EQ(one_error("M62\n"), "t.ngc:1:1: error: M62 needs a P word: the number of the digital output");
  EXPECT_EQ(one_error("M62 P64\n"), "t.ngc:1:5: error: M62 P64: digital outputs are numbered 0 … 63");
}

// M67 (synchronised with the next motion) and M68 (immediate) set analog output E to Q (LinuxCNC's
// four outputs, E0 … E3); one I/O M code a block, as M62…M66.
TEST(Iso, P10_AnalogOutputsM67M68) {
  const auto p = parse_ok("M67 E0 Q40.5\nM68 E3 Q-2\n");
  const auto a = all<AnalogOutput>(p);
  ASSERT_EQ(a.size(), 2u);
  EXPECT_EQ(a[0].index, 0);
  EXPECT_EQ(a[0].value, 40.5);
  EXPECT_TRUE(a[0].synced);
  EXPECT_EQ(a[1].index, 3);
  EXPECT_EQ(a[1].value, -2.0);
  EXPECT_FALSE(a[1].synced);
  EXPECT_EQ(all<MFunction>(p).at(0).number, 67);
  EXPECT_EQ(one_error("M67 Q1\n"), "t.ngc:1:1: error: M67 needs an E word: the number of the analog output (0 … 3)");
  EXPECT_EQ(one_error("M68 E4 Q1\n"), "t.ngc:1:5: error: M68 E4: analog outputs are numbered 0 … 3");
  EXPECT_EQ(one_error("M68 E1.5 Q1\n"), "t.ngc:1:5: error: M68 E1.5: analog outputs are numbered 0 … 3");
  EXPECT_EQ(one_error("M67 E1\n"), "t.ngc:1:1: error: M67 needs a Q word: the value to set");
  EXPECT_EQ(one_error("M67 E1 Q2 M62 P1\n"), "t.ngc:1:11: error: two M codes of group 14 in one block: M67 and M62");
  // Not under cutter compensation (LinuxCNC: "Cannot set motion output with cutter radius comp on").
  EXPECT_EQ(one_error("G21 F100\nG41.1 D2\nG1 X10\nM67 E0 Q1\nM2\n"),
            "t.ngc:4:1: error: M67 cannot set an output with cutter radius compensation on (G40 first)");
  EXPECT_EQ(one_error("G21 F100\nG41.1 D2\nG1 X10\nM62 P1\nM2\n"),
            "t.ngc:4:1: error: M62 cannot set an output with cutter radius compensation on (G40 first)");
}

TEST(IsoBlocks, ModalGroupConflictsNameBothCodes) {
  EXPECT_EQ(one_error("G17 G18\n"), "t.ngc:1:5: error: two plane selection codes in one block: G17 and G18");
  EXPECT_EQ(one_error("G54 G59.3\n"), "t.ngc:1:5: error: two coordinate system codes in one block: G54 and G59.3");
  EXPECT_EQ(one_error("G61 G64\n"), "t.ngc:1:5: error: two path control codes in one block: G61 and G64");
  EXPECT_EQ(one_error("G92 X0 G28\n"), "t.ngc:1:8: error: two non-modal codes in one block: G92 and G28");
  EXPECT_EQ(one_error("G1 G92 X0 F60\n"), "t.ngc:1:1: error: G92 and the motion code both use axis words: put them in separate blocks");
  EXPECT_EQ(one_error("G40 G41\n"), "t.ngc:1:5: error: two cutter compensation codes in one block: G40 and G41");
}

TEST(IsoCutterComp, G41RoutesMovesThroughTheCompensationStage) {
  const auto tt = tools_ok("T1 D2\n");
  iso::ParseOptions opt;
  opt.tools = &tt;
  const auto p = parse_ok("G0 X-10 Y0\nG41 D1 G1 X0 Y0 F60\nX20\nY20\nG40 G0 X30 Y30\n", opt);
  // The entry move ends offset to the left of the path (radius 1 mm): (0, 1).
  const auto e = ends(p);
  ASSERT_GE(e.size(), 3u);
  EXPECT_NEAR(e[1][0], 0, 1e-9);
  EXPECT_NEAR(e[1][1], 1, 1e-9);
  EXPECT_EQ(e.back(), xyz(30, 30));
  EXPECT_EQ(one_error("G41 D5\n"), "t.ngc:1:5: error: tool 5 is not in the tool table");
  EXPECT_EQ(one_error("G41.1 D2\nG41.1 D2\n"),
            "t.ngc:2:1: error: cutter radius compensation is already on: program G40 before turning it on again");
  EXPECT_EQ(one_error("G41.1 D2\nG81 X1 Z-1 R1 F60\n"),
            "t.ngc:2:1: error: canned cycles cannot run with cutter radius compensation on (G40 first)");
}

TEST(Iso, P12_FirstPathWordIsAlwaysEmitted) {
  // G61 equals the interpreter's initial state, but the machine's default (blending) applies until
  // the program names a mode: the first G61 must reach the channel; a repeated one need not.
  const auto p = parse_ok("G61\nG1 X10 F100\nG61\nG1 Y10\n");
  const auto modes = all<PathMode>(p);
  ASSERT_EQ(modes.size(), 1u);
  EXPECT_EQ(modes[0].kind, PathKind::ExactPath);
}
