// Fanuc-style subprograms in ISO programs: M98 P<n> [L<k>] calls O<n> … M99 (docs/gcode.md
// "Fanuc-style subprograms"). CAM posts for Fanuc, Haas and Mach3 controls put them after the main
// program's M30. The moves of kHoles and of the global-parameter test are those LinuxCNC 2.9's
// `rs274 -g` prints for the same programs; the packed P, definitions skipped where they stand and
// the errors are softmc's own rules (docs/gcode.md says where they differ from LinuxCNC).
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "iso_test_util.hpp"
#include "program/iso/lexer.hpp"

using namespace softmc;
using namespace softmc::program;
using namespace softmc::program::iso::test;

namespace {

// A row of holes drilled by a relative subprogram: the usual reason for M98 in a CAM post.
constexpr const char* kHoles =
    "O0001 (the program's own number: ignored)\n"  // 1
    "G21 G90 G17\n"                                // 2
    "G0 X0 Y0 Z5\n"                                // 3
    "F600\n"                                       // 4
    "M98 P1000 L3\n"                               // 5
    "G90 G0 X50 Y0\n"                              // 6
    "M98 P1000\n"                                  // 7
    "M30\n"                                        // 8
    "O1000 (one hole, 10 mm on)\n"                 // 9
    "G91 G0 X10\n"                                 // 10
    "G1 Z-6\n"                                     // 11
    "G0 Z6\n"                                      // 12
    "M99\n";                                       // 13

}  // namespace

TEST(IsoFanucSubprograms, M98RunsTheSubprogramLTimesAndComesBack) {
  const auto p = parse_ok(kHoles);
  const std::vector<core::Vec> want = {
      xyz(0, 0, 5),                                                // line 3
      xyz(10, 0, 5),  xyz(10, 0, -1), xyz(10, 0, 5),               // pass 1
      xyz(20, 0, 5),  xyz(20, 0, -1), xyz(20, 0, 5),               // pass 2
      xyz(30, 0, 5),  xyz(30, 0, -1), xyz(30, 0, 5),               // pass 3
      xyz(50, 0, 5),                                               // line 6, back in G90
      xyz(60, 0, 5),  xyz(60, 0, -1), xyz(60, 0, 5)};              // M98 without L: once
  EXPECT_EQ(ends(p), want);
  // The moves keep the subprogram's lines, so that errors and the trace point into it.
  EXPECT_EQ(p.instructions[1].loc.line, 10u);
  EXPECT_EQ(p.instructions.back().loc.line, 8u);  // the end
}

TEST(IsoFanucSubprograms, PackedPGivesPassesAndNumberAndNestedCallsReturnInOrder) {
  // Fanuc 0i/16i: P<passes><4-digit number> when no L is given and no O<P> exists. O2000 calls O1000.
  const auto p = parse_ok(
      "G0 X0 Y0\n"
      "M98 P22000\n"  // O2000 twice
      "M2\n"
      "O2000\n"
      "G91 G0 Y1\n"
      "M98 P1000\n"
      "G0 Y1\n"
      "M99\n"
      "O1000\n"
      "G91 G0 X1\n"
      "M99\n");
  const std::vector<core::Vec> want = {xyz(0, 0), xyz(0, 1), xyz(1, 1), xyz(1, 2),
                                       xyz(1, 3), xyz(2, 3), xyz(2, 4)};
  EXPECT_EQ(ends(p), want);
  // A five-digit subprogram number (Haas O00000–O99999) is that number when it exists.
  const auto h = parse_ok("G0 X0\nM98 P12345\nM2\nO12345\nG0 X7\nM99\n");
  EXPECT_EQ(ends(h), (std::vector<core::Vec>{xyz(0, 0), xyz(7, 0)}));
}

TEST(IsoFanucSubprograms, NumberedParametersAreSharedNamedLocalsAreNotAndL0RunsNothing) {
  // M98 passes no arguments: #1… are the caller's (a counter counts the passes), but a named local
  // is the subprogram's own, as in LinuxCNC (rs274 -g: X4, then X1 Y5 from the second program).
  const auto p = parse_ok(
      "#1 = 0\n"
      "M98 P10 L4\n"
      "M98 P10 L0\n"
      "G0 X#1\n"
      "M2\n"
      "O10\n"
      "#1 = [#1 + 1]\n"
      "M99\n");
  EXPECT_EQ(ends(p), std::vector<core::Vec>{xyz(4, 0)});
  const auto q = parse_ok(
      "G21 G90 F100\n"
      "#<i> = 1\n"
      "M98 P100\n"
      "G1 X#<i>\n"
      "M30\n"
      "O100\n"
      "#<i> = 5\n"
      "G1 Y#<i>\n"
      "M99\n");
  EXPECT_EQ(ends(q), (std::vector<core::Vec>{xyz(0, 5), xyz(1, 5)}));
}

TEST(IsoFanucSubprograms, ADefinitionBeforeTheProgramsEndIsAnError) {
  // LinuxCNC runs such lines as part of the main program; softmc would skip them: refused rather
  // than moved differently without a word. A main program ended by M99 is the usual case.
  EXPECT_EQ(one_error("G21 G90\nO0001 (MAIN)\nG0 X10\nG1 X20 F100\nM99\n"),
            "t.ngc:2:1: error: subprogram O1 (lines 2–5) stands before the program's end: softmc would skip it and "
            "LinuxCNC would run it here; put subprograms after M2/M30 (and end a main program with M2/M30, not M99)");
  // A bare O line that no M99 closes stays a program number, as LinuxCNC reads it.
  const auto p = parse_ok(
      "G0 X1\n"
      "O600 (a number, no subprogram: no M99 follows)\n"
      "G0 X2\n"
      "M98 P500\n"
      "M30\n"
      "O500\n"
      "G0 Y9\n"
      "M99\n");
  EXPECT_EQ(ends(p), (std::vector<core::Vec>{xyz(1, 0), xyz(2, 0), xyz(2, 9)}));
}

TEST(IsoFanucSubprograms, BadCallsAndReturnsAreErrorsNamingTheWord) {
  EXPECT_EQ(one_error("G0 X1\nM98\nM30\nO100\nG0 X2\nM99\n"),
            "t.ngc:2:1: error: M98 needs P: the number of the subprogram O<n> … M99 to call");
  EXPECT_EQ(one_error("G0 X1\nM98 P7\nM30\n"),
            "t.ngc:2:5: error: M98 P7: subprogram O7 is not in the program (a line O7 after the main program's first "
            "block, then its blocks, then M99)");
  EXPECT_EQ(one_error("G0 X1\nM98 P100 X5\nM30\nO100\nG0 X2\nM99\n"),
            "t.ngc:2:10: error: M98 stands alone on its line, with P (the subprogram) and L (how many times): X5 is "
            "not allowed here");
  EXPECT_EQ(one_error("G0 X1\nM98 P1.5\nM30\n"),
            "t.ngc:2:5: error: M98 P1.5: P is a subprogram number (a whole number, 0 or more)");
  EXPECT_EQ(one_error("G0 X1\nM98 P100 L-1\nM30\nO100\nG0 X2\nM99\n"),
            "t.ngc:2:10: error: M98 L-1: L is how many times to run it (a whole number, 0 or more)");
  EXPECT_EQ(one_error("G0 X1\nM98 P100\nM30\nO100\nG0 X2\nM99 P20\n"),
            "t.ngc:6:5: error: M99 P (return to a sequence number) is not supported: M99 returns after the M98");
  EXPECT_EQ(one_error("G0 X1\nM98 P100\nM30\nO100\nG0 X2\nG0 X3 M99\n"),
            "t.ngc:6:1: error: M99 stands alone on its line (with N): G0 is not allowed here");
  // An assignment on the M99 line would be dropped (rs274 stops there too).
  EXPECT_EQ(one_error("G0 X1\nM98 P100\nM30\nO100\nG0 X2\n#1=5 M99\n"),
            "t.ngc:6:1: error: M99 stands alone on its line (with N): set parameters on a line of their own");
  EXPECT_EQ(one_error("G0 X1\nM98 P100\nM30\nO100\n(ABORT, stop here) M99\n"),
            "t.ngc:5:1: error: the program aborts here (ABORT): stop here");
  // A '%' inside a subprogram (rs274: "Bad character '%' used").
  EXPECT_EQ(one_error("G0 X1\nM98 P100\nM30\nO100\n%\nG0 X3\nM99\n"),
            "t.ngc:5:1: error: '%' inside a subroutine or subprogram: '%' lines only open and close the program");
  // M99 in the main program would repeat it for ever on a Fanuc control.
  EXPECT_EQ(one_error("G0 X1\nM99\n"),
            "t.ngc:2:1: error: M99 outside a subprogram: M99 ends a subprogram (a line O<n> after the main program's "
            "first block, its blocks, then M99) that M98 P<n> calls; an M99 that repeats the main program for ever "
            "is not supported");
  // Endless recursion stops at the call depth.
  EXPECT_EQ(one_error("G0 X1\nM98 P100\nM30\nO100\nM98 P100\nM99\n"),
            "t.ngc:5:1: error: subprogram calls nested more than 32 deep (endless recursion?)");
}

TEST(IsoFanucSubprograms, StructureErrorsAreFoundBeforeAnythingRuns) {
  // The definition's error alone: no "not in the program" for the M98 that calls it.
  const auto open_if = parse_errors("G0 X1\nM98 P100\nM30\nO100\no1 if [1]\nG0 X2\nM99\no1 endif\n");
  EXPECT_NE(std::find(open_if.begin(), open_if.end(),
                      "t.ngc:7:1: error: M99 ends subprogram O100 (line 4) while o1 if (line 5) inside it is still open"),
            open_if.end());
  for (const auto& e : open_if) EXPECT_EQ(e.find("is not in the program"), std::string::npos) << e;
  const auto twice = parse_errors("G0 X1\nM98 P100\nM30\nO100\nG0 X2\nM99\nO0100\nG0 X3\nM99\n");
  EXPECT_EQ(twice.front(), "t.ngc:7:1: error: subprogram O100 (line 7) is defined twice");
  const auto inside = parse_errors("G0 X1\no1 if [1]\nO100\nG0 X2\nM99\no1 endif\nM30\n");
  EXPECT_EQ(inside.front(),
            "t.ngc:3:1: error: subprogram O100 (line 3) starts inside o1 if (line 2): subprograms stand on their own, "
            "outside every O-word structure");
}

TEST(IsoFanucSubprograms, TheM99ScanSeesOnlyTheWord) {
  // The control-flow index finds M99 lines with a quick scan; comments, named parameters and
  // function names that hold "m99" are not M99, and M099 is.
  EXPECT_EQ(iso::scan_m99("N10 M99"), 5u);
  EXPECT_EQ(iso::scan_m99("m 0 9 9 (return)"), 1u);
  EXPECT_EQ(iso::scan_m99("(M99) G0 X1"), 0u);
  EXPECT_EQ(iso::scan_m99("#<am99> = 1"), 0u);
  EXPECT_EQ(iso::scan_m99("G0 X1 ; M99"), 0u);
  EXPECT_EQ(iso::scan_m99("M9"), 0u);
  EXPECT_EQ(iso::scan_m99("M990"), 0u);
  EXPECT_EQ(iso::scan_m99("M99.5"), 0u);
  EXPECT_EQ(iso::scan_m99(" /M99"), 0u);  // block delete: not the end of a subprogram
  ASSERT_TRUE(iso::scan_program_number("N5 O0100 (holes)"));
  EXPECT_EQ(iso::scan_program_number("N5 O0100 (holes)")->name, "100");
  EXPECT_EQ(iso::scan_program_number("N5 O0100 (holes)")->col, 4u);
  EXPECT_FALSE(iso::scan_program_number("O100 call"));
  EXPECT_FALSE(iso::scan_program_number("o<name>"));
}
