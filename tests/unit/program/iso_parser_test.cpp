// ISO interpreter: modal motion, distance modes, units, arcs, dwell, M functions, program framing.
#include <gtest/gtest.h>

#include "iso_test_util.hpp"

using namespace softmc;
using namespace softmc::program;
using namespace softmc::program::iso::test;
using iso::ParseOptions;

namespace {
// An arc's end, centre in its plane and signed turns, each exactly.
void expect_arc(const Arc& a, const core::Vec& end, double c0, double c1, int turns) {
  EXPECT_EQ(a.end, end);
  EXPECT_EQ(a.center0, c0);
  EXPECT_EQ(a.center1, c1);
  EXPECT_EQ(a.turns, turns);
}
}  // namespace

TEST(IsoParser, ProgramRecordsFileAndStart) {
  ParseOptions opt;
  opt.start = xyz(1, 2, 3);
  const auto r = iso::parse("G0 X5\n", "part.ngc", opt);
  ASSERT_TRUE(r.program);
  EXPECT_EQ(r.program->files, std::vector<std::string>{"part.ngc"});
  EXPECT_EQ(r.program->start, xyz(1, 2, 3));
  // Axes not programmed keep their start position.
  EXPECT_EQ(op_at<Rapid>(*r.program, 0).end, xyz(5, 2, 3));
}

TEST(IsoParser, EmptyProgramIsValid) {
  const auto p = parse_ok("");
  EXPECT_TRUE(p.instructions.empty());
  EXPECT_TRUE(parse_ok("(just a comment)\n\n; and another\n").instructions.empty());
}

TEST(IsoParser, FeedIsConvertedFromMmPerMinute) {
  const auto p = parse_ok("G1 X10 F600");
  const auto& l = op_at<Linear>(p, 0);
  EXPECT_EQ(l.end, xyz(10, 0));
  EXPECT_DOUBLE_EQ(l.feed_mm_s, 10.0);
}

TEST(IsoParser, ModalMotionRepeatsTheLastMotionCode) {
  const auto p = parse_ok("G0 X1\nY2\nG1 X3 F60\nY4\nZ-1\n");
  ASSERT_EQ(p.instructions.size(), 5u);
  EXPECT_EQ(op_at<Rapid>(p, 0).end, xyz(1, 0));
  EXPECT_EQ(op_at<Rapid>(p, 1).end, xyz(1, 2));
  EXPECT_EQ(op_at<Linear>(p, 2).end, xyz(3, 2));
  EXPECT_EQ(op_at<Linear>(p, 3).end, xyz(3, 4));
  EXPECT_EQ(op_at<Linear>(p, 4).end, xyz(3, 4, -1));
  EXPECT_DOUBLE_EQ(op_at<Linear>(p, 4).feed_mm_s, 1.0);  // the feed stays in effect too
}

TEST(IsoParser, MotionCodeWithoutAxisWordsOnlySetsTheMode) {
  const auto p = parse_ok("G1 F60\nX5\nG0\nX0\n");
  ASSERT_EQ(p.instructions.size(), 2u);
  EXPECT_EQ(op_at<Linear>(p, 0).end, xyz(5, 0));
  EXPECT_EQ(op_at<Rapid>(p, 1).end, xyz(0, 0));
}

TEST(IsoParser, IncrementalMovesAddToThePosition) {
  ParseOptions opt;
  opt.start = xyz(1, 2, 3);
  const auto p = parse_ok("G91 G0 X1 Y1\nX1\nG1 Z-2 F60\nG90 X0\n", opt);
  ASSERT_EQ(p.instructions.size(), 4u);
  EXPECT_EQ(op_at<Rapid>(p, 0).end, xyz(2, 3, 3));
  EXPECT_EQ(op_at<Rapid>(p, 1).end, xyz(3, 3, 3));
  EXPECT_EQ(op_at<Linear>(p, 2).end, xyz(3, 3, 1));
  EXPECT_EQ(op_at<Linear>(p, 3).end, xyz(0, 3, 1));  // back to absolute in the same block
}

TEST(IsoParser, InchUnitsAreConvertedToMm) {
  const auto p = parse_ok("G20 G1 X1 Y-0.5 F10\nG91 X1\n");
  const auto& a = op_at<Linear>(p, 0);
  EXPECT_DOUBLE_EQ(a.end[0], 25.4);
  EXPECT_DOUBLE_EQ(a.end[1], -12.7);
  EXPECT_DOUBLE_EQ(a.feed_mm_s, 10 * 25.4 / 60);  // F in inch/min
  EXPECT_DOUBLE_EQ(op_at<Linear>(p, 1).end[0], 50.8);
}

TEST(IsoParser, FeedKeepsItsSpeedAcrossAUnitChange) {
  const auto p = parse_ok("G21 G1 X1 F60\nG20 X1\nG21 X2\n");
  EXPECT_DOUBLE_EQ(op_at<Linear>(p, 1).feed_mm_s, 1.0);
  EXPECT_DOUBLE_EQ(op_at<Linear>(p, 1).end[0], 25.4);
  EXPECT_DOUBLE_EQ(op_at<Linear>(p, 2).end[0], 2.0);
}

TEST(IsoParser, ExtraLinearAxesUVW) {
  const auto p = parse_ok("G0 U5 V-1 W2\n");
  const auto& r = op_at<Rapid>(p, 0);
  EXPECT_EQ(r.end[core::index(core::Axis::U)], 5.0);
  EXPECT_EQ(r.end[core::index(core::Axis::V)], -1.0);
  EXPECT_EQ(r.end[core::index(core::Axis::W)], 2.0);
}

TEST(IsoParser, CounterClockwiseArcG3) {
  ParseOptions opt;
  opt.start = xyz(10, 0);
  const auto p = parse_ok("G3 X0 Y10 I-10 J0 F60", opt);
  const auto& a = op_at<Arc>(p, 0);
  EXPECT_EQ(a.end, xyz(0, 10));
  EXPECT_EQ(a.center0, 0.0);
  EXPECT_EQ(a.center1, 0.0);
  EXPECT_EQ(a.turns, 1);
  EXPECT_EQ(a.axis0, 0);
  EXPECT_EQ(a.axis1, 1);
  EXPECT_EQ(a.normal, 2);
  EXPECT_DOUBLE_EQ(a.feed_mm_s, 1.0);
}

TEST(IsoParser, ClockwiseArcG2HasNegativeTurns) {
  ParseOptions opt;
  opt.start = xyz(10, 0);
  const auto p = parse_ok("G2 X0 Y10 I-10 F60", opt);  // a missing J is 0
  const auto& a = op_at<Arc>(p, 0);
  EXPECT_EQ(a.center0, 0.0);
  EXPECT_EQ(a.center1, 0.0);
  EXPECT_EQ(a.turns, -1);
}

TEST(IsoParser, PWordAddsFullTurns) {
  const auto p = parse_ok("G1 X10 F60\nG3 X10 Y0 I-10 P3\nG2 X10 Y0 I-10 P2\nG2 X10 Y0 I-10\n");
  EXPECT_EQ(op_at<Arc>(p, 1).turns, 3);
  EXPECT_EQ(op_at<Arc>(p, 2).turns, -2);
  EXPECT_EQ(op_at<Arc>(p, 3).turns, -1);  // end == start: one full circle
}

// Without plane words a centre-format arc is a full circle from where it stands, as LinuxCNC 2.9's
// rs274 reads it (ARC_FEED back to the start: `G2 I5 J0`, `G3 I5 K0` in G18, and a helix `G2 Z-1 I5 J0`).
TEST(IsoParser, ACentreArcWithoutPlaneWordsIsAFullCircle) {
  const auto p = parse_ok("G0 X10 Y10\nG2 I5 J0 F100\nG18\nG0 X0 Z0\nG3 I5 K0\nG17\nG2 Z-1 I5 J0\n");
  expect_arc(op_at<Arc>(p, 1), xyz(10, 10), 15.0, 10.0, -1);
  expect_arc(op_at<Arc>(p, 3), xyz(0, 10, 0), 0.0, 5.0, 1);  // G18: the plane (Z, X), centre Z0 X5, counter-clockwise
  expect_arc(op_at<Arc>(p, 4), xyz(0, 10, -1), 5.0, 10.0, -1);
}

TEST(IsoParser, HelixMovesZAlongTheArc) {
  const auto p = parse_ok("G0 X10\nG3 X-10 Y0 Z-5 I-10 F120\n");
  const auto& a = op_at<Arc>(p, 1);
  EXPECT_EQ(a.end, xyz(-10, 0, -5));
  EXPECT_EQ(a.center0, 0.0);
}

TEST(IsoParser, ArcCentreIsIncrementalFromTheStartEvenUnderG90) {
  // LinuxCNC's default G91.1: I and J are offsets from the arc's start point.
  const auto p = parse_ok("G90 G0 X40 Y10\nG3 X50 Y20 I0 J10 F480\n");
  const auto& a = op_at<Arc>(p, 1);
  EXPECT_EQ(a.center0, 40.0);
  EXPECT_EQ(a.center1, 20.0);
}

TEST(IsoParser, ArcEndIsIncrementalUnderG91) {
  const auto p = parse_ok("G0 X40 Y10\nG91 G3 X10 Y10 J10 F480\n");
  expect_arc(op_at<Arc>(p, 1), xyz(50, 20), 40.0, 20.0, 1);
}

TEST(IsoParser, AbsoluteArcCentreWithG90_1) {
  const auto p = parse_ok("G0 X40 Y10\nG90.1 G3 X50 Y20 I40 J20 F480\nG91.1 G1 X40 Y10\nG3 X50 Y20 J10\n");
  EXPECT_EQ(op_at<Arc>(p, 1).center0, 40.0);
  EXPECT_EQ(op_at<Arc>(p, 1).center1, 20.0);
  EXPECT_EQ(op_at<Arc>(p, 3).center1, 20.0);
}

TEST(IsoParser, InchArcCentreIsScaled) {
  ParseOptions opt;
  opt.start = xyz(25.4, 0);
  const auto p = parse_ok("G20 G3 X0 Y1 I-1 F10", opt);
  const auto& a = op_at<Arc>(p, 0);
  EXPECT_NEAR(a.center0, 0.0, 1e-12);
  EXPECT_DOUBLE_EQ(a.end[1], 25.4);
}

TEST(IsoParser, ModalArcTakesAxisWordsAlone) {
  const auto p = parse_ok("G0 X10\nG3 X0 Y10 I-10 F60\nX-10 Y0 I0 J-10\n");
  const auto& a = op_at<Arc>(p, 2);
  EXPECT_EQ(a.end, xyz(-10, 0));
  EXPECT_EQ(a.center0, 0.0);
  EXPECT_EQ(a.center1, 0.0);
  EXPECT_EQ(a.turns, 1);
}

TEST(IsoParser, DwellInSeconds) {
  const auto p = parse_ok("G4 P0.5\n");
  EXPECT_DOUBLE_EQ(op_at<Dwell>(p, 0).seconds, 0.5);
}

TEST(IsoParser, TorchMFunctionsComeWithTheirMNumberFirst) {
  const auto p = parse_ok("M3\nM4\nM5\n");
  ASSERT_EQ(p.instructions.size(), 6u);
  EXPECT_EQ(op_at<MFunction>(p, 0).number, 3);
  EXPECT_TRUE(op_at<ToolSwitch>(p, 1).on);
  EXPECT_EQ(op_at<MFunction>(p, 2).number, 4);
  EXPECT_TRUE(op_at<ToolSwitch>(p, 3).on);
  EXPECT_EQ(op_at<MFunction>(p, 4).number, 5);
  EXPECT_FALSE(op_at<ToolSwitch>(p, 5).on);
}

TEST(IsoParser, ProgramEnds) {
  const auto m2 = parse_ok("M2\n");
  EXPECT_EQ(op_at<MFunction>(m2, 0).number, 2);
  EXPECT_FALSE(op_at<ProgramEnd>(m2, 1).rewind);
  const auto m30 = parse_ok("M30\n");
  EXPECT_EQ(op_at<MFunction>(m30, 0).number, 30);
  EXPECT_TRUE(op_at<ProgramEnd>(m30, 1).rewind);
}

TEST(IsoParser, OrderOfExecutionInsideABlock) {
  // RS274 order: feed, torch (M3/M5), dwell, modes, motion, program end - whatever the word order.
  const auto p = parse_ok("M30 X10 G4 P1 M3 F60 G1\n");
  ASSERT_EQ(p.instructions.size(), 6u);
  EXPECT_EQ(op_at<MFunction>(p, 0).number, 3);
  EXPECT_TRUE(op_at<ToolSwitch>(p, 1).on);
  EXPECT_DOUBLE_EQ(op_at<Dwell>(p, 2).seconds, 1.0);
  EXPECT_EQ(op_at<Linear>(p, 3).end, xyz(10, 0));
  EXPECT_EQ(op_at<MFunction>(p, 4).number, 30);
  EXPECT_TRUE(op_at<ProgramEnd>(p, 5).rewind);
  // The torch goes off before the motion of its block, as in LinuxCNC.
  const auto q = parse_ok("G1 X10 F60 M5\n");
  EXPECT_FALSE(op_at<ToolSwitch>(q, 1).on);
  EXPECT_EQ(op_at<Linear>(q, 2).end, xyz(10, 0));
}

TEST(IsoParser, InstructionsCarryTheBlockStart) {
  const auto p = parse_ok("\n  N10 G0 X1 M3\n\tG1 F60 Y1\n");
  ASSERT_EQ(p.instructions.size(), 4u);
  for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(p.instructions[i].loc, (core::SourceLoc{0, 2, 3})) << i;
  EXPECT_EQ(p.instructions[3].loc, (core::SourceLoc{0, 3, 2}));
}

TEST(IsoParser, LineNumbersMayHaveAFraction) {
  // LinuxCNC's read_n_number accepts and ignores a fraction: rs274 -g runs "N20.5 G1 X2" as
  // STRAIGHT_FEED(2, 0, 0). A negative one is an error there too ("Bad format unsigned integer").
  const auto p = parse_ok("N20.5 G1 X2 F60\n");
  EXPECT_EQ(op_at<Linear>(p, 0).end, xyz(2, 0));
  EXPECT_EQ(one_error("N-5 G1 X2 F60\n"), "t.ngc:1:1: error: line number (N word) must be 0 or more");
}

TEST(IsoParser, PercentDelimitsTheProgram) {
  const auto p = parse_ok("%\nG0 X1\n%\nthis is not read: G0 X2 #@!\n");
  ASSERT_EQ(p.instructions.size(), 1u);
  EXPECT_EQ(op_at<Rapid>(p, 0).end, xyz(1, 0));
  // A '%' after blocks of a program that did not open with one is an error, as rs274's "Bad character
  // '%' used": the moves after it are not silently dropped.
  EXPECT_EQ(one_error("G0 X1\n%\nG0 X2\n"),
            "t.ngc:2:1: error: '%' closes the program, but it did not open with a '%' line");
  // Comments and blank lines before the opening '%' are no blocks.
  EXPECT_EQ(parse_ok("(header)\n\n%\nG0 X1\n%\nG0 X2\n").instructions.size(), 1u);
}

TEST(IsoParser, TextAfterProgramEndIsIgnoredWithAWarning) {
  const auto r = iso::parse("M30\n%\n", "t.ngc");
  ASSERT_TRUE(r.program);
  EXPECT_TRUE(r.diagnostics.empty());
  const auto w = iso::parse("G0 X1\nM2\n\n(comment)\nG0 X5\nG0 bad\n", "t.ngc");
  ASSERT_TRUE(w.program);
  EXPECT_EQ(w.program->instructions.size(), 3u);
  EXPECT_EQ(formatted(w), std::vector<std::string>{"t.ngc:5:1: warning: text after the program end (M2/M30) is ignored"});
}

TEST(IsoParser, BlockDeleteSkipsTheLine) {
  const auto p = parse_ok("G0 X1\n/G0 X5\n/ anything at all (\nG0 Y1\n");
  ASSERT_EQ(p.instructions.size(), 2u);
  EXPECT_EQ(op_at<Rapid>(p, 1).end, xyz(1, 1));
}

TEST(IsoParser, CommentsCaseAndSpacing) {
  const auto p = parse_ok("g1x1 F 6 0 (set feed)\n  x 2 ; comment\r\nN20 y3\n");
  ASSERT_EQ(p.instructions.size(), 3u);
  EXPECT_DOUBLE_EQ(op_at<Linear>(p, 0).feed_mm_s, 1.0);
  EXPECT_EQ(op_at<Linear>(p, 1).end, xyz(2, 0));
  EXPECT_EQ(op_at<Linear>(p, 2).end, xyz(2, 3));
}

TEST(IsoParser, PreambleCodesOfTheDefaultStateAreAccepted) {
  const auto p = parse_ok("G17 G21 G40 G49 G54 G80 G90 G94\nG0 X1\n");
  ASSERT_EQ(p.instructions.size(), 1u);
}

TEST(IsoParser, ArcEndWithinLinuxCncToleranceIsAccepted) {
  // Radius 10 at the start, 10.02 at the end: 0.02 mm <= 0.028 mm (LinuxCNC's 0.02·√2 mm).
  const auto p = parse_ok("G0 X10\nG3 X0 Y10.02 I-10 F60\n");
  EXPECT_EQ(op_at<Arc>(p, 1).center0, 0.0);
  // Large arcs get 0.1 % of the radius: 0.5 mm off on a 1000 mm radius is accepted.
  parse_ok("G0 X1000\nG3 X0 Y1000.5 I-1000 F60\n");
  // Inch programs get LinuxCNC's inch tolerance, 0.002·√2 in = 0.072 mm: 0.002 in off is accepted.
  parse_ok("G20 G0 X1\nG3 X0 Y1.002 I-1 F1\n");
}

TEST(IsoParser, DumpOfASmallProgram) {
  const auto p = parse_ok("G0 X1 Y2\nG1 X3 F120\nG2 X5 Y2 I1 J-1 P2\nG4 P0.25\nM3\nM30\n");
  EXPECT_EQ(dump(p),
            "start X0.000000 Y0.000000 Z0.000000\n"
            "    1:1   rapid X1.000000 Y2.000000 Z0.000000\n"
            "    2:1   feed X3.000000 Y2.000000 Z0.000000 F2.000000\n"
            "    3:1   arc X5.000000 Y2.000000 Z0.000000 CX4.000000,Y1.000000 NZ turns -2 F2.000000\n"
            "    4:1   dwell 0.250000\n"
            "    5:1   m 3\n"
            "    5:1   tool on\n"
            "    6:1   m 30\n"
            "    6:1   end rewind\n");
}

TEST(IsoParser, ParseFileReadsTheFile) {
  const auto r = iso::parse_file(std::string(SOFTMC_SOURCE_DIR) + "/examples/thesis/square.ngc");
  ASSERT_TRUE(r.program);
  EXPECT_EQ(r.program->files[0], std::string(SOFTMC_SOURCE_DIR) + "/examples/thesis/square.ngc");
}

TEST(IsoParser, UnreadableFileIsADiagnosticAtLineZero) {
  for (const std::string& path : {std::string("/nonexistent/dir/x.ngc"), std::string(SOFTMC_SOURCE_DIR)}) {
    const auto r = iso::parse_file(path);
    EXPECT_FALSE(r.program);
    ASSERT_EQ(r.diagnostics.size(), 1u);
    EXPECT_EQ(r.diagnostics[0].format(), path + ":0:0: error: cannot read file");
  }
}
