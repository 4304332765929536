// ISO parser errors: each names file:line:col of the offending word; recovery reports them all.
#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "iso_test_util.hpp"

using namespace softmc;
using namespace softmc::program;
using namespace softmc::program::iso::test;

TEST(IsoDiagnostics, FeedMissingNamesLineAndColumnOfTheMotionWord) {
  EXPECT_EQ(one_error("G21 G90\nG0 X1\nG1 X10\n"),
            "t.ngc:3:1: error: feed rate missing: program an F word before the first feed move");
  EXPECT_EQ(one_error("N5 G0 X1\nN6 X2 G2 I1\n"),
            "t.ngc:2:7: error: feed rate missing: program an F word before the first feed move");
  EXPECT_EQ(one_error("(no feed yet) G1 X1\n"),
            "t.ngc:1:15: error: feed rate missing: program an F word before the first feed move");
  EXPECT_EQ(one_error("G0 X1\nG1\n"), "t.ngc:2:1: error: feed rate missing: program an F word before the first feed move");
}

TEST(IsoDiagnostics, FeedMustBePositive) {
  // LinuxCNC takes F0 and refuses the feed move that needs it (rs274 -g: "Cannot do g1 with zero feed
  // rate", "Cannot make arc with zero feed rate", "Cannot feed with zero feed rate" for G81); "F0"
  // alone and "G0 X1 F0" run. A negative F is refused at the word ("Negative f word used").
  EXPECT_EQ(one_error("G1 X1 F0\n"), "t.ngc:1:1: error: feed rate is 0: a feed move needs an F greater than 0");
  EXPECT_EQ(one_error("F0\nG2 X2 I1\n"), "t.ngc:2:1: error: feed rate is 0: a feed move needs an F greater than 0");
  // Before the geometry, as a missing F (an arc without its centre would be the second error).
  EXPECT_EQ(parse_errors("F0\nG2 X2\n").front(), "t.ngc:2:1: error: feed rate is 0: a feed move needs an F greater than 0");
  EXPECT_EQ(one_error("F0\nG0 Z5\nG81 X1 Z-1 R1\n"), "t.ngc:3:1: error: feed rate is 0: a feed move needs an F greater than 0");
  EXPECT_EQ(one_error("F100\nG1 X1\nF0\nX2\n"), "t.ngc:4:1: error: feed rate is 0: a feed move needs an F greater than 0");
  EXPECT_EQ(one_error("G1 X1 F-60\n"), "t.ngc:1:7: error: feed rate (F) must be 0 or more");
  const auto p = parse_ok("F0\nG0 X1 F0\nG1 X2 F60\n");
  EXPECT_EQ(op_at<Linear>(p, 1).feed_mm_s, 1.0);
}

TEST(IsoDiagnostics, TwoMotionWordsInOneBlock) {
  EXPECT_EQ(one_error("G0 G1 X1 F60\n"), "t.ngc:1:4: error: two motion codes in one block: G0 and G1");
  EXPECT_EQ(one_error("G2 X1 G3\n"), "t.ngc:1:7: error: two motion codes in one block: G2 and G3");
  EXPECT_EQ(one_error("G20 G21\n"), "t.ngc:1:5: error: two units codes in one block: G20 and G21");
  EXPECT_EQ(one_error("M3 M5\n"), "t.ngc:1:4: error: two M codes of group 2 in one block: M3 and M5");
}

TEST(IsoDiagnostics, UnknownAndUnsupportedWords) {
  EXPECT_EQ(one_error("G1 X1 E5 F60\n"), "t.ngc:1:7: error: E word with nothing to use it (it goes with M66, M67/M68)");
  EXPECT_EQ(one_error("G33.1 X1\n"),
            "t.ngc:1:1: error: G33.1 (spindle-synchronised motion) is not supported: the machine has no spindle feedback");
  EXPECT_EQ(one_error("G33 X1 K1\n"),
            "t.ngc:1:1: error: G33 (spindle-synchronised motion) is not supported: the machine has no spindle feedback");
  EXPECT_EQ(one_error("G95\n"),
            "t.ngc:1:1: error: G95 (feed per revolution) is not supported: the machine has no spindle feedback");
  EXPECT_EQ(one_error("G12\n"), "t.ngc:1:1: error: unsupported G code G12");
  EXPECT_EQ(one_error("G1.25\n"), "t.ngc:1:1: error: malformed G code G1.25: at most one decimal place");
  EXPECT_EQ(one_error("M200\n"), "t.ngc:1:1: error: unknown M code M200 (M0 … M199)");
  EXPECT_EQ(one_error("M3.5\n"), "t.ngc:1:1: error: malformed M code M3.5: M codes are whole numbers");
  // Fanuc-style M98 P<n> / O<n> … M99 subprograms run (iso_fanuc_subprogram_test.cpp); a call of one
  // that is not there names it and says what a definition looks like.
  EXPECT_EQ(one_error("M98 P100 L2\n"),
            "t.ngc:1:5: error: M98 P100: subprogram O100 is not in the program (a line O100 after the main "
            "program's first block, then its blocks, then M99)");
  EXPECT_EQ(one_error("G33 X1 K1\n").rfind("t.ngc:1:1: error: G33 (spindle-synchronised motion) is not supported", 0), 0u);
  // G84 is a floating-holder cycle at the programmed F (LinuxCNC 2.9): it needs the spindle turning clockwise.
  EXPECT_EQ(one_error("F100 G84 X1 Z-1 R1\n"), "t.ngc:1:6: error: spindle not turning in G84: program M3 S… first");
}

TEST(IsoDiagnostics, MalformedNumberAtTheWord) {
  EXPECT_EQ(one_error("G0 X1\nG1 Y2.3.4 F60\n"), "t.ngc:2:4: error: malformed number: two decimal points");
  EXPECT_EQ(one_error("G0 X\n"), "t.ngc:1:4: error: X word has no number");
  EXPECT_EQ(one_error("G0 X1e999\n"), "t.ngc:1:4: error: number out of range");
}

TEST(IsoDiagnostics, RepeatedLetterInOneBlock) {
  EXPECT_EQ(one_error("G0 X1 X2\n"), "t.ngc:1:7: error: two X words in one block");
  EXPECT_EQ(one_error("G1 X1 F60 F70\n"), "t.ngc:1:11: error: two F words in one block");
}

TEST(IsoDiagnostics, AxisWordsBeforeAnyMotionMode) {
  EXPECT_EQ(one_error("G21\n  X10 Y5\n"),
            "t.ngc:2:3: error: axis words with no motion mode: program G0, G1, G2 or G3 first");
  EXPECT_EQ(one_error("G0 X1\nG80\nX2\n"),
            "t.ngc:3:1: error: axis words with no motion mode: program G0, G1, G2 or G3 first");
}

TEST(IsoDiagnostics, WordsWithNothingToUseThem) {
  EXPECT_EQ(one_error("G1 X1 I2 F60\n"), "t.ngc:1:7: error: I word with nothing to use it (it goes with G2/G3 arcs, G5/G5.1 splines, G87)");
  EXPECT_EQ(one_error("G0 X1 J2\n"), "t.ngc:1:7: error: J word with nothing to use it (it goes with G2/G3 arcs, G5/G5.1 splines, G87)");
  EXPECT_EQ(one_error("G0 X1 H2\n"), "t.ngc:1:7: error: H word with nothing to use it (it goes with G43)");
  EXPECT_EQ(one_error("G0 X1 P2\n").rfind("t.ngc:1:7: error: P word with nothing to use it (it goes with G4", 0), 0u);
  EXPECT_EQ(one_error("G4\n"), "t.ngc:1:1: error: G4 needs a P word: the dwell time in seconds");
  EXPECT_EQ(one_error("G4 P-1\n"), "t.ngc:1:4: error: dwell time (P) must be 0 or more");
  EXPECT_EQ(one_error("G0 X1 N5\n"), "t.ngc:1:7: error: line number (N word) must be the first word of the block");
}

TEST(IsoDiagnostics, ArcErrors) {
  EXPECT_EQ(one_error("G0 X10\nG3 X0 Y10 F60\n"),
            "t.ngc:2:1: error: I and J words both missing: give the arc centre with I and/or J");
  EXPECT_EQ(one_error("G0 X10\nG3 R10 F60\n"), "t.ngc:2:1: error: X and Y words both missing for an R-format arc");
  EXPECT_EQ(one_error("G0 X10\nG3 X0 Y10 I0 J0 F60\n"),
            "t.ngc:2:1: error: zero-radius arc: centre (10.0000, 0.0000) is on the start or end point");
  EXPECT_EQ(one_error("G0 X10\nG3 X0 Y10 I-10 P0 F60\n"),
            "t.ngc:2:16: error: arc turns (P) must be a whole number, 1 or more");
  EXPECT_EQ(one_error("G0 X10\nG3 X0 Y10 I-10 P1.5 F60\n"),
            "t.ngc:2:16: error: arc turns (P) must be a whole number, 1 or more");
}

TEST(IsoDiagnostics, ArcEndOffTheCircleIsRefused) {
  // 0.05 mm off a 10 mm radius: above LinuxCNC's 0.028 mm and above 0.1 % of the radius.
  EXPECT_EQ(one_error("G0 X10\nG3 X0 Y10.05 I-10 F60\n"),
            "t.ngc:2:1: error: arc end point is not on the circle: radius 10.0000 mm at the start, 10.0500 mm at "
            "the end (they differ by 0.05 mm, at most 0.02828 mm allowed)");
  // Modal arc: the error points at the first axis word.
  EXPECT_EQ(one_error("G0 X10\nG3 X0 Y10 I-10 F60\n  X-10 Y1 J-10\n").rfind("t.ngc:3:3: error: arc end point", 0), 0u);
  // 1.5 mm off a 1000 mm radius is 0.15 %: refused.
  parse_errors("G0 X1000\nG3 X0 Y1001.5 I-1000 F60\n");
  // The same 0.002 in that inch programs may be off is too much in a mm program.
  parse_errors("G0 X25.4\nG3 X0 Y25.4508 I-25.4 F60\n");
  // Beyond 100 × 0.028 mm even a huge radius does not help (LinuxCNC's hard limit).
  parse_errors("G0 X100000\nG3 X0 Y100003 I-100000 F60\n");
}

TEST(IsoDiagnostics, RecoveryReportsEveryErrorInSourceOrder) {
  const auto e = parse_errors(
      "G21 G90\n"
      "G0 X1 X2\n"       // repeated word
      "G1 X5 F100\n"     // fine
      "G1 Y1.2.3\n"      // malformed number
      "X6\n"             // fine: modal G1
      "M200\n"           // unknown M code
      "M30\n");
  EXPECT_EQ(e, (std::vector<std::string>{"t.ngc:2:7: error: two X words in one block",
                                         "t.ngc:4:4: error: malformed number: two decimal points",
                                         "t.ngc:6:1: error: unknown M code M200 (M0 … M199)"}));
}

TEST(IsoDiagnostics, AFailedFeedWordIsNotReportedAgainAsMissingFeed) {
  // The root cause is the bad F; the moves after it must not each complain about a missing feed.
  EXPECT_EQ(parse_errors("G1 X1 F1.2.3\nX2\nX3\n"),
            std::vector<std::string>{"t.ngc:1:7: error: malformed number: two decimal points"});
  EXPECT_EQ(parse_errors("G12 X1\nX2\nX3\n"), std::vector<std::string>{"t.ngc:1:1: error: unsupported G code G12"});
}

TEST(IsoDiagnostics, AFailedG5_3IsNotEchoedAtTheEnd) {
  // The G5.3 fails for the missing feed; its block's end inside the program must not be reported
  // twice more (once on a line after the last: a fuzzer's program).
  EXPECT_EQ(parse_errors("G0 X5 Y5\nG5.2 X10 Y-20 L3\nX20 Y5\nG5.3\nM30\n"),
            std::vector<std::string>{"t.ngc:4:1: error: feed rate missing: program an F word before the first feed move"});
  EXPECT_EQ(parse_errors("G0 X5 Y5\nG5.2 X10 Y-20 L3\nX20 Y5\nG5.3\n").size(), 1u);  // no M30
  // A G5.2 left open without a failing G5.3 is still reported.
  EXPECT_EQ(parse_errors("G0 X5 Y5 F60\nG5.2 X10 Y-20 L3\nX20 Y5\nM30\n").size(), 1u);
}

// A G5.2 block the file leaves open is reported at its G5.2 word, not at a line after the last.
TEST(IsoDiagnostics, AG5_2LeftOpenIsReportedWhereItOpened) {
  EXPECT_EQ(parse_errors("G0 X5 Y5 F60\nG5.2 X10 Y-20 L3\nX20 Y5\nG5.3\n  G5.2 X0 Y0 L3\nX20 Y5\n"),
            std::vector<std::string>{"t.ngc:5:3: error: the program ends inside this G5.2 block: close it with G5.3"});
}

TEST(IsoDiagnostics, NoProgramWhenAnyError) {
  const auto r = iso::parse("G0 X1\nG1 X2 F60\nG0 Q1\n", "t.ngc");
  EXPECT_FALSE(r.program);
  ASSERT_EQ(r.diagnostics.size(), 1u);
  EXPECT_EQ(r.diagnostics[0].line, 3u);
  EXPECT_EQ(r.diagnostics[0].col, 4u);
  EXPECT_EQ(r.diagnostics[0].file, "t.ngc");
  EXPECT_EQ(r.diagnostics[0].severity, core::Severity::Error);
}

TEST(IsoDiagnostics, TooManyErrorsStopWithANote) {
  std::string text;
  for (int i = 0; i < 150; ++i) text += "Q1\n";
  const auto r = iso::parse(text, "t.ngc");
  EXPECT_FALSE(r.program);
  ASSERT_EQ(r.diagnostics.size(), 101u);
  EXPECT_EQ(r.diagnostics[99].line, 100u);
  EXPECT_EQ(r.diagnostics.back().format(), "t.ngc:101:1: note: too many errors (100); stopping here");
}

TEST(IsoDiagnostics, NonFiniteStartIsRefused) {
  iso::ParseOptions opt;
  opt.start[0] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(parse_errors("G0 X1\n", opt), std::vector<std::string>{"t.ngc:0:0: error: start position is not finite"});
}
