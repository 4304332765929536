// M70 / M71 / M72 / M73: LinuxCNC's save and restore of modal state (docs/gcode.md, "Saving and
// restoring modal state"). Where the expected values are DEBUG texts, they are what LinuxCNC 2.9's
// `rs274 -g` printed for the same program.
#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include "iso_test_util.hpp"

using namespace softmc;
using namespace softmc::program;
using namespace softmc::program::iso::test;

namespace {

// The program's dump lines made at `line` (dump(): "  line:col text"), without the location.
std::vector<std::string> made_at(const Program& p, std::uint32_t line) {
  std::vector<std::string> out;
  std::istringstream in(dump(p));
  const std::string prefix = std::to_string(line) + ":";
  for (std::string s; std::getline(in, s);) {
    const auto first = s.find_first_not_of(' ');
    if (first == std::string::npos || s.compare(first, prefix.size(), prefix) != 0) continue;
    const auto text = s.find_first_not_of(' ', s.find(' ', first));
    out.push_back(s.substr(text));
  }
  return out;
}

constexpr const char* kShowState =
    "o<show> sub\n"
    "(DEBUG, imperial=#<_imperial> absolute=#<_absolute> feed=#<_feed> rpm=#<_rpm>)\n"
    "o<show> endsub\n";

}  // namespace

// LinuxCNC's m70m72-demo.ngc: M70 before a subroutine that changes units, distance mode, F and S,
// M72 after it gives the caller's modes back.
TEST(IsoModalState, M70AndM72RestoreTheCallersModesAroundASubroutine) {
  const auto p = parse_ok(std::string(kShowState) +
                          "o<imperialsub> sub\n"
                          "G20 G91 F5 S300\n"
                          "o<show> call\n"
                          "o<imperialsub> endsub\n"
                          "G21 G90 F200 S2500\n"
                          "o<show> call\n"
                          "M70\n"
                          "o<imperialsub> call\n"
                          "M72\n"
                          "o<show> call\n"
                          "G1 X10\n"
                          "M2\n");
  const std::vector<std::string> want = {" imperial=0.000000 absolute=1.000000 feed=200.000000 rpm=2500.000000",
                                         " imperial=1.000000 absolute=0.000000 feed=5.000000 rpm=300.000000",
                                         " imperial=0.000000 absolute=1.000000 feed=200.000000 rpm=2500.000000"};
  EXPECT_EQ(messages(p), want);
  // The move after the restore runs in mm, absolute, at F200 mm/min again.
  const auto& last = op_at<Linear>(p, p.instructions.size() - 3);
  EXPECT_DOUBLE_EQ(last.end[0], 10.0);
  EXPECT_DOUBLE_EQ(last.feed_mm_s, 200.0 / 60.0);
}

// LinuxCNC's m73-demo.ngc: M73 in a subroutine restores the caller's modes at its endsub and at a
// return, whichever ends it; the main program's modes are never touched by what it changed.
TEST(IsoModalState, M73RestoresOnEndsubAndOnReturn) {
  const auto p = parse_ok(std::string(kShowState) +
                          "o<imperialsub> sub\n"
                          "M73\n"
                          "G20 G91 F5 S300\n"
                          "o<show> call\n"
                          "o100 if [#1 GT 0]\n"
                          "  o<imperialsub> return\n"
                          "o100 endif\n"
                          "o<imperialsub> endsub\n"
                          "G21 G90 F200 S2500\n"
                          "o<imperialsub> call [0]\n"
                          "o<show> call\n"
                          "o<imperialsub> call [1]\n"
                          "o<show> call\n"
                          "M2\n");
  const std::string main = " imperial=0.000000 absolute=1.000000 feed=200.000000 rpm=2500.000000";
  const std::string sub = " imperial=1.000000 absolute=0.000000 feed=5.000000 rpm=300.000000";
  EXPECT_EQ(messages(p), (std::vector<std::string>{sub, main, sub, main}));
}

// The restore emits what the codes themselves would, for what differs only: the PLC sees the
// spindle, coolant and override M functions again, the Channel the offsets and the path mode.
TEST(IsoModalState, M72EmitsWhatTheRestoredCodesWould) {
  const auto p = parse_ok(
      "G21 G90 G17 G64 P0.1 F100 S1000 M3 M8 G55\n"
      "M70\n"
      "G20 G91 G18 G61 F5 S300 M4 M9 G57 M49 G98 G93\n"
      "M72\n"
      "(DEBUG, #<_imperial> #<_absolute> #<_plane> #<_coord_system> #<_spindle_cw> #<_flood> #<_feed> #<_rpm> "
      "#<_feed_override> #<_retract_old_z> #<_inverse_time>)\n"
      "G1 X1\n"
      "M70\n"
      "M72\n"
      "M2\n");
  // LinuxCNC prints the same but for feed=0: its restore loses F where the feed mode changes back
  // (and then refuses the G1 "with zero feed rate"); softmc restores F as it was saved.
  EXPECT_EQ(messages(p), (std::vector<std::string>{" 0.000000 1.000000 170.000000 550.000000 1.000000 1.000000 "
                                                   "100.000000 1000.000000 1.000000 0.000000 0.000000"}));
  EXPECT_EQ(made_at(p, 4), (std::vector<std::string>{
                               "spindle 1000.000000 rpm", "m 3", "tool on", "m 8", "m 48",
                               "offsets cs2 work X0.000000 Y0.000000 Z0.000000 axis X0.000000 Y0.000000 Z0.000000 "
                               "tool X0.000000 Y0.000000 Z0.000000 R0.000000",
                               "path blend P0.100000 Q0.100000"}));
  EXPECT_EQ(made_at(p, 6), (std::vector<std::string>{"feed X1.000000 Y0.000000 Z0.000000 F1.666667"}));
  EXPECT_TRUE(made_at(p, 8).empty());  // nothing differs: nothing programmed again
}

// Cutter compensation saved off is turned off by the restore, as G40 would (the moves are
// rs274 -g's for the same program); saved on it cannot be turned on again by M72, which is an
// error at its line and the program is not made.
TEST(IsoModalState, M72TurnsCutterCompensationOffButNotOn) {
  const auto p = parse_ok(
      "G21 G90 G17 F100\n"
      "G0 X0 Y0\n"
      "M70\n"
      "G41.1 D2\n"
      "G1 X10 Y0\n"
      "G1 X10 Y10\n"
      "M72\n"
      "G1 X0 Y10\n"
      "(DEBUG, #<_ccomp>)\n"
      "M2\n");
  EXPECT_EQ(ends(p), (std::vector<core::Vec>{xyz(0, 0), xyz(9, 1), xyz(9, 10), xyz(0, 10)}));
  EXPECT_EQ(messages(p), (std::vector<std::string>{" 400.000000"}));

  EXPECT_EQ(one_error("G21 G90 G17 F100\n"
                      "G41.1 D2\n"
                      "G1 X10 Y0\n"
                      "M70\n"
                      "G40\n"
                      "G1 X10 Y10\n"
                      "M72\n"
                      "M2\n"),
            "t.ngc:7:1: error: M72: cannot restore cutter compensation left (G41) (radius 1 mm): program G41/G42 "
            "again after the restore (LinuxCNC would turn it on with the current tool's radius)");
}

// The tool length offset comes back to the bit, a G43.1 one too (LinuxCNC re-runs a bare G43.1
// there, which gives zero offsets).
TEST(IsoModalState, M72RestoresTheToolLengthOffsetToTheBit) {
  const auto p = parse_ok(
      "G20 G90 F10\n"
      "G43.1 Z0.3\n"
      "M70\n"
      "G49\n"
      "M72\n"
      "(DEBUG, #<_tool_offset>)\n"
      "G0 Z0\n"
      "M2\n");
  EXPECT_EQ(messages(p), (std::vector<std::string>{" 1.000000"}));
  EXPECT_EQ(ends(p).back()[2], 0.3 * 25.4);
}

// G43 comes back as G43: the offset of the tool loaded now (rs274 -g: T2's 12.7 mm, not T1's),
// and a G43 H2 made since is kept (the code is the same).
TEST(IsoModalState, M72ProgramsG43AgainForTheToolLoadedNow) {
  const auto tt = tools_ok("T1 P1 Z25.4 D3\nT2 P2 Z12.7 D6\n");
  iso::ParseOptions opt;
  opt.tools = &tt;
  const auto p = parse_ok("G21 G90\nT1 M6\nG43\nM70\nT2 M6\nG49\nM72\nG0 Z10\nM70\nG43 H1\nM72\nG0 Z0\nM2\n", opt);
  EXPECT_EQ(ends(p), (std::vector<core::Vec>{xyz(0, 0, 22.7), xyz(0, 0, 25.4)}));
}

// A restore's error at an endsub or return names its word.
TEST(IsoModalState, AnM73RestoreErrorNamesTheReturnsWord) {
  EXPECT_EQ(one_error("G21 G90 F100\nG41.1 D2\nG1 X10 Y0\no1 sub\n    M73\n    G40\n    G1 X20 Y0\n    o1 endsub\n"
                      "o1 call\nM2\n"),
            "t.ngc:8:5: error: the return restores the modes M73 saved: cannot restore cutter compensation left (G41) "
            "(radius 1 mm): program G41/G42 again after the restore (LinuxCNC would turn it on with the current "
            "tool's radius)");
}

// Each call level keeps its own saved state: a subroutine cannot restore what the main program
// saved, M71 invalidates, and a recursive call saves and restores at each level.
TEST(IsoModalState, EachCallLevelHasItsOwnSavedState) {
  EXPECT_EQ(one_error("G21\n"
                      "o<s> sub\n"
                      "M72\n"
                      "o<s> endsub\n"
                      "M70\n"
                      "o<s> call\n"
                      "M2\n"),
            "t.ngc:3:1: error: M72 with no modal state saved at this call level: M70 or M73 first (a subroutine's "
            "saved state is its own, the main program's its own)");
  EXPECT_EQ(one_error("G21\nM70\nG20\nM71\nM72\nM2\n"),
            "t.ngc:5:1: error: M72 with no modal state saved at this call level: M70 or M73 first (a subroutine's "
            "saved state is its own, the main program's its own)");
  // Depth 3 → 1: level 3 switches to inches, the others to G91; each return gives its caller's modes
  // back (rs274 -g prints the same).
  const auto p = parse_ok(
      "o<r> sub\n"
      "M73\n"
      "o10 if [#1 EQ 3]\n"
      "  G20\n"
      "o10 else\n"
      "  G91\n"
      "o10 endif\n"
      "o20 if [#1 GT 1]\n"
      "  o<r> call [#1 - 1]\n"
      "o20 endif\n"
      "(DEBUG, level #1 #<_imperial> #<_incremental>)\n"
      "o<r> endsub\n"
      "G21 G90\n"
      "o<r> call [3]\n"
      "(DEBUG, main #<_imperial> #<_incremental>)\n"
      "M2\n");
  EXPECT_EQ(messages(p), (std::vector<std::string>{" level 1.000000 1.000000 1.000000", " level 2.000000 1.000000 1.000000",
                                                   " level 3.000000 1.000000 0.000000", " main 0.000000 0.000000"}));
}

// A Fanuc-style subprogram's M73 restores at its M99, at every pass of an M98 L (each pass is a
// call of its own, as in LinuxCNC: rs274 -g gives the same moves, 0.1 inch each, from mm absolute).
TEST(IsoModalState, M73InAFanucSubprogramRestoresAtEachM99) {
  const auto p = parse_ok(
      "G21 G90 F100\n"
      "M98 P100 L2\n"
      "(DEBUG, #<_imperial> #<_incremental> #<_feed>)\n"
      "M30\n"
      "O100\n"
      "M73\n"
      "G20 F2\n"
      "G91 G1 X0.1\n"
      "M99\n");
  EXPECT_EQ(messages(p), (std::vector<std::string>{" 0.000000 0.000000 100.000000"}));
  EXPECT_EQ(ends(p), (std::vector<core::Vec>{xyz(2.54, 0), xyz(5.08, 0)}));
}

// Misuse is an error at the word, and nothing is made.
TEST(IsoModalState, MisuseIsAnErrorAtTheWord) {
  EXPECT_EQ(one_error("G21\nM70 G20\nM2\n"), "t.ngc:2:5: error: M70 stands alone on its line (with N): G20 is not "
                                            "allowed here");
  EXPECT_EQ(one_error("G21\nM72\nM2\n"), "t.ngc:2:1: error: M72 with no modal state saved at this call level: M70 or "
                                        "M73 first (a subroutine's saved state is its own, the main program's its own)");
  // The machine's default path mode (no G61/G64 yet) cannot be programmed back.
  EXPECT_EQ(one_error("G21\nM70\nG64 P0.2\nM72\nM2\n"),
            "t.ngc:4:1: error: M72: cannot restore the machine's default path mode: no G61/G61.1/G64 was in effect "
            "when the state was saved; program one before M70/M73");
  // N on the line is fine.
  parse_ok("G21\nN10 M70\nN20 M72 (back)\nM2\n");
}
