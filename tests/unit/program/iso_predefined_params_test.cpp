// LinuxCNC's predefined named parameters (#<_x>, #<_motion_mode>, …; docs/gcode.md). The expected
// values are what LinuxCNC 2.9's `rs274 -g` printed for the same (DEBUG, …) lines.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "iso_test_util.hpp"

using namespace softmc;
using namespace softmc::program;
using namespace softmc::program::iso::test;

TEST(IsoPredefinedParameters, ModesPositionsAndWordsAsLinuxCncGivesThem) {
  const auto p = parse_ok(
      "G21 G90 G17 G10 L2 P2 X1 Y2 Z3\n"
      "G55 G0 X10 Y20 Z5\n"
      "F600 S1000 M3 M8\n"
      "G1 X11\n"
      "(DEBUG, #<_line> #<_motion_mode> #<_plane> #<_ccomp> #<_metric> #<_absolute> #<_coord_system>)\n"
      "(DEBUG, #<_x> #<_y> #<_z> #<_abs_x> #<_abs_y> #<_abs_z> #<_feed> #<_rpm>)\n"
      "(DEBUG, #<_spindle_on> #<_spindle_cw> #<_mist> #<_flood> #<_feed_override> #<_retract_r_plane>)\n"
      "G20 G91 G18 G56 G93 G98 S200 M4 M7 M49 G90.1\n"
      "T3 M61 Q3\n"
      "G1 X1 F30\n"
      "(DEBUG, #<_line> #<_plane> #<_imperial> #<_incremental> #<_inverse_time> #<_coord_system>)\n"
      "(DEBUG, #<_x> #<_y> #<_z> #<_abs_z> #<_feed> #<_rpm> #<_selected_tool> #<_ijk_absolute_mode>)\n"
      "(DEBUG, #<_spindle_on> #<_spindle_cw> #<_mist> #<_flood> #<_feed_override> #<_retract_old_z>)\n"
      "G96 S300 D2000\n"
      "S250\n"
      "(DEBUG, #<_spindle_css_mode> #<_rpm>)\n");
  const std::vector<std::string> want = {
      " 5.000000 10.000000 170.000000 400.000000 1.000000 1.000000 550.000000",
      " 11.000000 20.000000 5.000000 12.000000 22.000000 8.000000 600.000000 1000.000000",
      " 1.000000 1.000000 0.000000 1.000000 1.000000 1.000000",
      // In G20 the positions are in inches: 1 inch on from X 11 mm.
      " 11.000000 180.000000 1.000000 1.000000 1.000000 560.000000",
      " 1.472441 0.866142 0.314961 0.314961 30.000000 200.000000 3.000000 1.000000",
      " 1.000000 0.000000 1.000000 1.000000 0.000000 1.000000",
      " 1.000000 250.000000"};
  EXPECT_EQ(messages(p), want);
}

TEST(IsoPredefinedParameters, CallLevelCountsSubroutinesAndSubprograms) {
  const auto p = parse_ok(
      "o<s> sub\n"
      "(DEBUG, #<_call_level> #<_line>)\n"
      "o<s> endsub\n"
      "(DEBUG, #<_call_level>)\n"
      "o<s> call\n"
      "M98 P100\n"
      "(DEBUG, #<_call_level> #<_motion_mode>)\n"
      "M2\n"
      "O100\n"
      "(DEBUG, #<_call_level>)\n"
      "M99\n");
  EXPECT_EQ(messages(p), (std::vector<std::string>{" 0.000000", " 1.000000 2.000000", " 1.000000",
                                                    " 0.000000 800.000000"}));
}

TEST(IsoPredefinedParameters, TheyAreReadOnlyAndThePositionNumbersFollowTheUnits) {
  // LinuxCNC: "Cannot assign to read-only parameter #<_x>".
  EXPECT_EQ(one_error("G21\n#<_x> = 3\n"), "t.ngc:2:1: error: named parameter #<_x> is read-only");
  // #5420… are in program units too (they were in mm under G20).
  const auto p = parse_ok("G20 G0 X1 Y2\n(DEBUG, #5420 #5421)\n");
  EXPECT_EQ(messages(p), std::vector<std::string>{" 1.000000 2.000000"});
  // Other globals are still the program's own.
  const auto g = parse_ok("#<_mine> = 4\n(DEBUG, #<_mine>)\n");
  EXPECT_EQ(messages(g), std::vector<std::string>{" 4.000000"});
}

TEST(IsoPredefinedParameters, ToolOffsetMeansANonZeroOffsetAndG96KeepsItsLimit) {
  // rs274 -g: #<_tool_offset> is 0 under G43.1 Z0 and 1 under G43.1 Z5.
  const auto p = parse_ok("G21\nG43.1 Z0\n(DEBUG, #<_tool_offset>)\nG43.1 Z5\n(DEBUG, #<_tool_offset>)\n");
  EXPECT_EQ(messages(p), (std::vector<std::string>{" 0.000000", " 1.000000"}));
  // G96 S200 D3000, then S300 alone: still a surface speed, still under 3000 rpm (rs274 keeps
  // SET_SPINDLE_MODE(0 3000) and only sets the speed).
  const auto g = parse_ok("G21\nG96 S200 D3000 M3\nS300\nG97 S1000\n");
  std::vector<SpindleSpeed> s;
  for (const auto& i : g.instructions)
    if (const auto* sp = std::get_if<SpindleSpeed>(&i.op)) s.push_back(*sp);
  ASSERT_EQ(s.size(), 3u);
  EXPECT_TRUE(s[1].css);
  EXPECT_EQ(s[1].surface_m_min, 300);
  EXPECT_EQ(s[1].max_rpm, 3000);
  EXPECT_FALSE(s[2].css);
  EXPECT_EQ(s[2].rpm, 1000);
}

TEST(IsoPredefinedParameters, AFeedModeChangeNeedsANewFeed) {
  // LinuxCNC sets the feed to 0 at G93/G94: after G93 … G94, "G1 X3" without F is refused
  // ("Cannot do g1 with zero feed rate") and #<_feed> is 0. softmc does so where the mode changes.
  const auto p = parse_ok("G21 G94 F300\nG1 X1\nG94\nG1 X2\nG93 G1 X3 F10\nG94\n(DEBUG, #<_feed>)\nG1 X4 F200\n");
  EXPECT_EQ(messages(p), std::vector<std::string>{" 0.000000"});
  EXPECT_EQ(one_error("G21 G94 F300\nG93 G1 X1 F10\nG94\nG1 X3\n").rfind("t.ngc:4:", 0), 0u);
}

// Under cutter compensation the position parameters give where the tool is: the programmed end
// moved by the tool radius along the move's normal there (before the next move's corner is known),
// as LinuxCNC's #5420… and #<_abs_x>… do. Expected values are rs274 -g's for the same program.
TEST(IsoPredefinedParameters, PositionUnderCutterCompensationIsTheTools) {
  const auto p = parse_ok(
      "G20 G17 G90 G40 G55 G10 L2 P2 X1 Y2\n"
      "G0 X0 Y0 Z1\n"
      "G42.1 D0.5\n"
      "G1 X3 Y0 F10\n"
      "(DEBUG, #5420 #5421 #5422 #<_abs_x> #<_abs_y>)\n"
      "G1 Z-0.1\n"
      "(DEBUG, #5420 #5421 #5422)\n"
      "G2 X3 Y-4 I0 J-2\n"
      "(DEBUG, #5420 #5421)\n"
      "G91 G1 X-3\n"
      "(DEBUG, #5420 #5421 #<_x>)\n"
      "G90 G40 G0 X0 Y0\n"
      "(DEBUG, #5420 #5421)\n");
  const std::vector<std::string> want = {
      " 3.000000 -0.250000 1.000000 4.000000 1.750000",  // entry move: offset right of +X
      " 3.000000 -0.250000 -0.100000",                   // a plunge keeps the offset point
      " 3.000000 -3.750000",                             // inside the R2 arc, towards its centre
      " 0.000000 -3.750000 0.000000",                    // G91 moves from the programmed point
      " 0.000000 0.000000"};                             // G40: the programmed point again
  EXPECT_EQ(messages(p), want);
}

// A G40 on a line of its own gives the programmed point back at once (#5420… and the base of a G91
// move), while the next move starts where the tool is: rs274 -g gives the same ends and values.
TEST(IsoPredefinedParameters, AfterABareG40ThePositionIsTheProgrammedPoint) {
  const auto p = parse_ok(
      "G21 G90 G64 P0.1 F100\n"
      "G0 X0 Y0\n"
      "G41.1 D2\n"
      "G1 X10 Y0\n"
      "G1 X10 Y10\n"
      "G40\n"
      "(DEBUG, #5420 #5421)\n"
      "G91 G1 X-5\n"
      "(DEBUG, #<_x> #<_y>)\n");
  EXPECT_EQ(ends(p), (std::vector<core::Vec>{xyz(0, 0), xyz(9, 1), xyz(9, 10), xyz(5, 10)}));
  EXPECT_EQ(messages(p), (std::vector<std::string>{" 10.000000 10.000000", " 5.000000 10.000000"}));
}
