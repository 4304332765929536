// Cutter radius (kerf) compensation: exact offset geometry of real parts, corners, and gouge errors.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "iso_test_util.hpp"
#include "program/iso/cutter_comp.hpp"

using namespace softmc;
using namespace softmc::program;
using namespace softmc::program::iso;
using namespace softmc::program::iso::test;

namespace {

constexpr double kTol = 1e-9;

// Runs the motions of a parsed program through compensation: instructions before index `from`
// pass uncompensated (the approach), then G41/G42 is switched on, and G40 at the end.
struct CompRun {
  std::vector<Instruction> out;
  std::optional<CompError> error;
};

CompRun compensate(const Program& p, std::size_t from, CompSide side, double radius) {
  CompRun r;
  CutterComp comp;
  core::Vec pos = p.start;
  for (std::size_t i = 0; i < from; ++i) {
    r.out.push_back(p.instructions[i]);
    if (const auto* m = std::get_if<Rapid>(&p.instructions[i].op)) pos = m->end;
    if (const auto* m = std::get_if<Linear>(&p.instructions[i].op)) pos = m->end;
  }
  EXPECT_FALSE(comp.start(side, radius, 0, 1, pos).has_value());
  for (std::size_t i = from; i < p.instructions.size() && !r.error; ++i) r.error = comp.push(p.instructions[i], r.out);
  if (!r.error) comp.stop(r.out);
  return r;
}

std::vector<Instruction> motions(const std::vector<Instruction>& v) {
  std::vector<Instruction> m;
  for (const auto& i : v)
    if (is_motion(i.op)) m.push_back(i);
  return m;
}

::testing::AssertionResult at_xy(const core::Vec& v, double x, double y) {
  if (std::fabs(v[0] - x) < kTol && std::fabs(v[1] - y) < kTol) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << fmt::format("at ({:.9f}, {:.9f}), expected ({}, {})", v[0], v[1], x, y);
}

const char* kSquare =
    "G21 G90 G17\n"
    "G0 X-10 Y0\n"   // 2: approach
    "G1 X0 Y0 F600\n"  // 3: entry along the bottom edge
    "G1 X20 Y0\n"    // 4
    "G1 X20 Y20\n"   // 5
    "G1 X0 Y20\n"    // 6
    "G1 X0 Y0\n"     // 7
    "G1 X20 Y0\n"    // 8: closes the last corner
    "M30\n";

}  // namespace

// Outside cut of a square (counter-clockwise, tool right = G42): every edge moves out by the kerf
// radius and each convex corner is rounded by an arc of that radius about the programmed corner.
TEST(IsoCutterComp, SquareOutsideOffsetsEdgesAndRoundsCorners) {
  const auto p = parse_ok(kSquare);
  const auto run = compensate(p, 1, CompSide::Right, 0.5);
  ASSERT_FALSE(run.error) << run.error->message;
  const auto m = motions(run.out);
  ASSERT_EQ(m.size(), 1u + 1u + 1u + 4u * 2u - 1u + 1u);  // approach, entry, edge, 3×(corner, edge), corner, edge
  EXPECT_TRUE(at_xy(std::get<Rapid>(m[0].op).end, -10, 0));
  EXPECT_TRUE(at_xy(std::get<Linear>(m[1].op).end, 0, -0.5));  // entry: perpendicular offset at its end
  EXPECT_TRUE(at_xy(std::get<Linear>(m[2].op).end, 20, -0.5));
  struct Corner {
    double cx, cy, ex, ey;  // corner arc centre and end
    double lx, ly;          // end of the offset edge after it
  };
  const Corner kCorners[] = {{20, 0, 20.5, 0, 20.5, 20}, {20, 20, 20, 20.5, 0, 20.5}, {0, 20, -0.5, 20, -0.5, 0},
                             {0, 0, 0, -0.5, 20, -0.5}};
  for (std::size_t k = 0; k < 4; ++k) {
    const auto& a = std::get<Arc>(m[3 + 2 * k].op);
    EXPECT_EQ(a.turns, 1) << k;  // counter-clockwise about the corner, tool on the right
    EXPECT_NEAR(a.center0, kCorners[k].cx, kTol) << k;
    EXPECT_NEAR(a.center1, kCorners[k].cy, kTol) << k;
    EXPECT_TRUE(at_xy(a.end, kCorners[k].ex, kCorners[k].ey)) << k;
    EXPECT_TRUE(at_xy(std::get<Linear>(m[4 + 2 * k].op).end, kCorners[k].lx, kCorners[k].ly)) << k;
    EXPECT_EQ(m[3 + 2 * k].loc.line, 5u + k) << "the corner belongs to the move after it";
  }
}

// Inside cut (tool left = G41) of the same square: edges move in, corners are cut back to the
// intersection of the offset edges, which gives the exact inner square.
TEST(IsoCutterComp, SquareInsideIntersectsOffsetEdges) {
  const auto p = parse_ok(
      "G21 G90\nG0 X10 Y10\nG1 X10 Y0 F600\nG1 X20 Y0\nG1 X20 Y20\nG1 X0 Y20\nG1 X0 Y0\nG1 X20 Y0\nM30\n");
  const auto run = compensate(p, 1, CompSide::Left, 0.5);
  ASSERT_FALSE(run.error) << run.error->message;
  const auto m = motions(run.out);
  ASSERT_EQ(m.size(), 7u);  // approach, entry, five edges; no corner arcs
  EXPECT_TRUE(at_xy(std::get<Linear>(m[1].op).end, 10.5, 0.5));  // the entry is cut back too
  EXPECT_TRUE(at_xy(std::get<Linear>(m[2].op).end, 19.5, 0.5));
  EXPECT_TRUE(at_xy(std::get<Linear>(m[3].op).end, 19.5, 19.5));
  EXPECT_TRUE(at_xy(std::get<Linear>(m[4].op).end, 0.5, 19.5));
  EXPECT_TRUE(at_xy(std::get<Linear>(m[5].op).end, 0.5, 0.5));
  EXPECT_TRUE(at_xy(std::get<Linear>(m[6].op).end, 20, 0.5));  // last move, released by G40 uncut
  for (const auto& i : m) EXPECT_FALSE(std::holds_alternative<Arc>(i.op));
}

// The thesis' rounded rectangle (cutting_table.md T-3) cut outside with a 0.5 mm kerf: tangent
// line-arc joints need no corner; lines move out 0.5 mm, arcs keep their centres at radius 10.5.
TEST(IsoCutterComp, T3_RoundedRectangleKerfOutside) {
  const auto r = parse_file(std::string(SOFTMC_SOURCE_DIR) + "/examples/thesis/rounded_rectangle.ngc");
  ASSERT_TRUE(r.program);
  const auto run = compensate(*r.program, 1, CompSide::Right, 0.5);
  ASSERT_FALSE(run.error) << run.error->message;
  const auto m = motions(run.out);
  ASSERT_EQ(m.size(), 9u);
  EXPECT_TRUE(at_xy(std::get<Linear>(m[1].op).end, 40, 9.5));
  const double kCentres[4][2] = {{40, 20}, {40, 40}, {20, 40}, {20, 20}};
  const double kLineEnds[3][2] = {{50.5, 40}, {20, 50.5}, {9.5, 20}};
  for (std::size_t k = 0; k < 4; ++k) {
    const auto& a = std::get<Arc>(m[2 + 2 * k].op);
    EXPECT_NEAR(a.center0, kCentres[k][0], kTol);
    EXPECT_NEAR(a.center1, kCentres[k][1], kTol);
    EXPECT_NEAR(std::hypot(a.end[0] - a.center0, a.end[1] - a.center1), 10.5, kTol) << k;
    EXPECT_EQ(a.turns, 1);
    if (k < 3) {
      EXPECT_TRUE(at_xy(std::get<Linear>(m[3 + 2 * k].op).end, kLineEnds[k][0], kLineEnds[k][1])) << k;
    }
  }
  EXPECT_TRUE(at_xy(std::get<Arc>(m[8].op).end, 20, 9.5));
  // The torch M functions stay in program order around the moves.
  EXPECT_EQ(std::get<MFunction>(run.out[1].op).number, 3);
}

// Same part, inside (a hole of that shape): arcs shrink to radius 9.5, lines move in.
TEST(IsoCutterComp, T3_RoundedRectangleKerfInside) {
  const auto r = parse_file(std::string(SOFTMC_SOURCE_DIR) + "/examples/thesis/rounded_rectangle.ngc");
  ASSERT_TRUE(r.program);
  const auto run = compensate(*r.program, 1, CompSide::Left, 0.5);
  ASSERT_FALSE(run.error) << run.error->message;
  const auto m = motions(run.out);
  ASSERT_EQ(m.size(), 9u);
  EXPECT_TRUE(at_xy(std::get<Linear>(m[1].op).end, 40, 10.5));
  for (std::size_t k = 0; k < 4; ++k) {
    const auto& a = std::get<Arc>(m[2 + 2 * k].op);
    EXPECT_NEAR(std::hypot(a.end[0] - a.center0, a.end[1] - a.center1), 9.5, kTol) << k;
  }
}

// Down a wall into a tangent bowl (counter-clockwise half circle) and up the other wall: tangent
// joints need no corner; the tool (left) is inside the bowl, so the arc shrinks to radius R - r.
TEST(IsoCutterComp, TangentLineArcJointsNeedNoCorner) {
  const auto p = parse_ok("G21 G90\nG0 X0 Y30\nG1 X0 Y20 F600\nG1 X0 Y10\nG3 X20 Y10 I10 J0\nG1 X20 Y30\nM30\n");
  const auto run = compensate(p, 1, CompSide::Left, 1.0);
  ASSERT_FALSE(run.error) << run.error->message;
  const auto m = motions(run.out);
  ASSERT_EQ(m.size(), 5u);  // approach, entry, wall, bowl, wall
  EXPECT_TRUE(at_xy(std::get<Linear>(m[1].op).end, 1, 20));
  EXPECT_TRUE(at_xy(std::get<Linear>(m[2].op).end, 1, 10));
  const auto& a = std::get<Arc>(m[3].op);
  EXPECT_TRUE(at_xy(a.end, 19, 10));
  EXPECT_NEAR(a.center0, 10, kTol);
  EXPECT_NEAR(a.center1, 10, kTol);
  EXPECT_TRUE(at_xy(std::get<Linear>(m[4].op).end, 19, 30));
}

// A real inside corner between a line and an arc: the offset line and the offset circle meet.
TEST(IsoCutterComp, LineToArcConcaveCorner) {
  // Go east along y=0, then a ccw arc of radius 10 starting at (10,0) about (10,10) heading... east is tangent,
  // so start the arc at (10,0) about (20,0) (heading north, a left turn of 90°).
  const auto p = parse_ok("G21 G90\nG0 X-10 Y0\nG1 X0 Y0 F600\nG1 X10 Y0\nG2 X20 Y10 I10 J0\nM30\n");
  // Travel east then turn north: a left turn; with the tool left (G41) that is an inside corner.
  const auto run = compensate(p, 1, CompSide::Left, 1.0);
  ASSERT_FALSE(run.error) << run.error->message;
  const auto m = motions(run.out);
  ASSERT_EQ(m.size(), 4u);
  const auto& line = std::get<Linear>(m[2].op);
  const auto& arc = std::get<Arc>(m[3].op);
  // Cut-back point: on the offset line y = 1 and on the offset circle about (20,0): the clockwise
  // arc has the tool (left) outside, so radius 10 + 1.
  EXPECT_NEAR(line.end[1], 1.0, kTol);
  EXPECT_NEAR(std::hypot(line.end[0] - 20, line.end[1] - 0), 11.0, kTol);
  EXPECT_LT(line.end[0], 10.0);  // cut back before the programmed corner
  EXPECT_NEAR(std::hypot(arc.end[0] - 20, arc.end[1] - 0), 11.0, kTol);
  EXPECT_TRUE(at_xy(arc.end, 20, 11));
}

// Two clockwise arcs meeting at a sharp joint (20,0): the first goes over the top of the circle
// about (10,0) and arrives heading down; the second (about (30,-5)) leaves heading up and right.
// Tool left (outside both circles): an inside corner, cut back to where the offset circles meet.
// Tool right (inside both): an outside corner, joined by an arc about the joint.
TEST(IsoCutterComp, ArcToArcCorners) {
  const auto p = parse_ok("G21 G90\nG0 X-10 Y0\nG1 X0 Y0 F600\nG2 X20 Y0 I10 J0\nG2 X40 Y0 I10 J-5\nM30\n");
  const double r2 = std::hypot(10.0, 5.0);
  const auto left = compensate(p, 1, CompSide::Left, 1.0);
  ASSERT_FALSE(left.error) << left.error->message;
  const auto ml = motions(left.out);
  ASSERT_EQ(ml.size(), 4u);
  const auto& a1 = std::get<Arc>(ml[2].op);
  EXPECT_NEAR(std::hypot(a1.end[0] - 10, a1.end[1]), 11.0, kTol);
  EXPECT_NEAR(std::hypot(a1.end[0] - 30, a1.end[1] + 5), r2 + 1.0, kTol);
  EXPECT_GT(a1.end[1], 0.0);
  EXPECT_LT(std::hypot(a1.end[0] - 20, a1.end[1]), 3.0);  // the intersection next to the joint

  const auto right = compensate(p, 1, CompSide::Right, 1.0);
  ASSERT_FALSE(right.error) << right.error->message;
  const auto mr = motions(right.out);
  ASSERT_EQ(mr.size(), 6u);  // the entry's corner into the first arc is outside too
  const auto& corner = std::get<Arc>(mr[4].op);
  EXPECT_NEAR(corner.center0, 20.0, kTol);
  EXPECT_NEAR(corner.center1, 0.0, kTol);
  EXPECT_EQ(corner.turns, 1);
  EXPECT_TRUE(at_xy(std::get<Arc>(mr[3].op).end, 19, 0));
  EXPECT_TRUE(at_xy(corner.end, 20 + 2 / std::sqrt(5.0), -1 / std::sqrt(5.0)));
  EXPECT_NEAR(std::hypot(std::get<Arc>(mr[5].op).end[0] - 30, std::get<Arc>(mr[5].op).end[1] + 5), r2 - 1.0, kTol);
}

// A pocket narrower than the tool: the offset edges cross, the path would reverse: an error that
// names the line and column of the move that reveals it.
TEST(IsoCutterComp, ImpossibleInsideCornerIsAnErrorWithLineAndColumn) {
  const auto p = parse_ok("G21 G90\nG0 X2 Y10\nG1 X2 Y0 F600\n  G1 X4 Y0\nG1 X4 Y4\nG1 X0 Y4\nM30\n");
  const auto run = compensate(p, 1, CompSide::Left, 3.0);  // a 6 mm tool in a 4 mm pocket
  ASSERT_TRUE(run.error);
  EXPECT_EQ(run.error->loc.line, 4u);
  EXPECT_EQ(run.error->loc.col, 3u);
  EXPECT_NE(run.error->message.find("gouge"), std::string::npos) << run.error->message;
  EXPECT_NE(run.error->message.find("radius 3 mm"), std::string::npos) << run.error->message;
}

TEST(IsoCutterComp, ToolLargerThanInsideArcIsAnError) {
  const auto p = parse_ok("G21 G90\nG0 X-10 Y0\nG1 X0 Y0 F600\nG3 X4 Y0 I2 J0\nM30\n");
  const auto run = compensate(p, 1, CompSide::Left, 2.5);  // tool left of a ccw arc: inside it
  ASSERT_TRUE(run.error);
  EXPECT_EQ(run.error->loc.line, 4u);
  EXPECT_NE(run.error->message.find("not less than the arc radius"), std::string::npos) << run.error->message;
}

TEST(IsoCutterComp, EntryMoveMustBeLongerThanTheRadius) {
  const auto p = parse_ok("G21 G90\nG0 X0 Y0\nG1 X1 Y0 F600\nM30\n");
  const auto run = compensate(p, 1, CompSide::Left, 1.0);
  ASSERT_TRUE(run.error);
  EXPECT_EQ(run.error->loc.line, 3u);
  EXPECT_NE(run.error->message.find("entry move"), std::string::npos);
}

// Plunges (no motion in the plane) keep the tool at its offset point, and a plunge held after a
// move whose end is cut back at an inside corner follows the new end.
TEST(IsoCutterComp, PlungesStayAtTheToolOffsetAndKeepOrder) {
  const auto p = parse_ok("G21 G90\nG0 X10 Y10\nG1 X10 Y0 F600\nG1 Z-2\nG4 P1\nG1 X20 Y0\nM30\n");
  const auto run = compensate(p, 1, CompSide::Left, 0.5);
  ASSERT_FALSE(run.error) << run.error->message;
  ASSERT_GE(run.out.size(), 5u);
  EXPECT_TRUE(at_xy(std::get<Linear>(run.out[1].op).end, 10.5, 0.5));  // entry, cut back
  const auto& plunge = std::get<Linear>(run.out[2].op);
  EXPECT_TRUE(at_xy(plunge.end, 10.5, 0.5));
  EXPECT_DOUBLE_EQ(plunge.end[2], -2.0);
  EXPECT_TRUE(std::holds_alternative<Dwell>(run.out[3].op));
  EXPECT_TRUE(at_xy(std::get<Linear>(run.out[4].op).end, 20, 0.5));
  EXPECT_DOUBLE_EQ(std::get<Linear>(run.out[4].op).end[2], -2.0);
}

TEST(IsoCutterComp, StartTwiceIsRefusedAndAShortEntryArcToo) {
  CutterComp c;
  EXPECT_FALSE(c.start(CompSide::Left, 1, 0, 1, core::Vec{}));
  EXPECT_TRUE(c.start(CompSide::Left, 1, 0, 1, core::Vec{}));
  std::vector<Instruction> out;
  Arc a;  // an entry arc (clockwise: the tool outside it) whose chord is not longer than the tool radius
  a.end = xyz(0.5, 0.5);
  a.center0 = 0.5;
  a.turns = -1;
  const auto e = c.push(Instruction{{0, 7, 3}, a}, out);
  ASSERT_TRUE(e);
  EXPECT_EQ(e->loc.line, 7u);
  EXPECT_NE(e->message.find("entry arc"), std::string::npos) << e->message;
  EXPECT_TRUE(out.empty());
}

// LinuxCNC 2.9 (convert_arc_comp1) allows an arc as the entry move: it ends at the programmed end
// moved by the tool radius along the radius (inside: towards the centre), about a centre moved
// along that radius so that the arc starts at the tool: a true arc, no spiral. Same numbers as
// rs274 prints for tests/golden/iso/plasma_arc_leadin.ngc (its hole).
TEST(IsoCutterComp, ArcEntryMovesTheCentreLikeLinuxCnc) {
  const auto p = parse_ok("G21 G90 G17\nG0 X30 Y20\nF600\nG41.1 D4\nG3 X30 Y12 I0 J-4\nG3 X30 Y12 I0 J8\n"
                          "G3 X34 Y16 I0 J4\nG40\nM30\n");
  const auto m = motions(p.instructions);
  ASSERT_EQ(m.size(), 4u);
  const auto& entry = std::get<Arc>(m[1].op);
  EXPECT_TRUE(at_xy(entry.end, 30, 14));
  EXPECT_NEAR(entry.center0, 30, kTol);
  EXPECT_NEAR(entry.center1, 17, kTol);
  EXPECT_EQ(entry.turns, 1);
  // A true arc: the tool's start and the end are equally far from the centre.
  EXPECT_NEAR(std::hypot(30 - entry.center0, 20 - entry.center1),
              std::hypot(entry.end[0] - entry.center0, entry.end[1] - entry.center1), kTol);
  const auto& circle = std::get<Arc>(m[2].op);  // the hole, radius 8 - 2, tangent to the entry
  EXPECT_TRUE(at_xy(circle.end, 30, 14));
  EXPECT_NEAR(circle.center1, 20, kTol);
  EXPECT_TRUE(at_xy(std::get<Arc>(m[3].op).end, 32, 16));  // lead-out, radius 4 - 2
}

// An outside entry arc (G42, clockwise quarter onto the bottom edge of a part): the centre moves
// below the programmed one, as rs274 prints (ARC_FEED(0, -0.75, 0, -6.8036, -1)).
TEST(IsoCutterComp, OutsideArcEntryMatchesRs274) {
  const auto p = parse_ok("G21 G90 G17\nG0 X-6 Y-6\nF2400\nG42.1 D1.5\nG2 X0 Y0 I6 J0\nG1 X60 Y0\nG40\nM30\n");
  const auto m = motions(p.instructions);
  ASSERT_GE(m.size(), 3u);
  const auto& entry = std::get<Arc>(m[1].op);
  EXPECT_TRUE(at_xy(entry.end, 0, -0.75));
  EXPECT_NEAR(entry.center0, 0, 1e-4);
  EXPECT_NEAR(entry.center1, -6.8036, 1e-4);
  EXPECT_LT(entry.turns, 0);
  EXPECT_TRUE(at_xy(std::get<Linear>(m[2].op).end, 60, -0.75));
}

// A G0/G1 with no axis words moves nothing, with and without compensation (rs274 prints a
// zero-length STRAIGHT_FEED for it; softmc makes no instruction: there is no geometry to plan).
TEST(IsoCutterComp, BareG1MakesNoMove) {
  const auto with = parse_ok("G21 G90 G17\nG0 X0 Y0\nF600\nG41.1 D4\nG1 X20 Y0\nG1\nG1 X20 Y20\nG1\nG40\nM30\n");
  const auto without = parse_ok("G21 G90 G17\nG0 X0 Y0\nF600\nG1 X20 Y0\nG1\nG0\nG1 X20 Y20\nG1\nM30\n");
  for (const auto* p : {&with, &without}) {
    for (const auto& ins : p->instructions) {
      EXPECT_NE(ins.loc.line, 6u) << dump(*p);
      EXPECT_NE(ins.loc.line, 8u) << dump(*p);
    }
  }
  EXPECT_EQ(motions(without.instructions).size(), 3u);
}

// An error leaves the stage unchanged: the same stage accepts a good move afterwards.
TEST(IsoCutterComp, ErrorLeavesStateUnchanged) {
  CutterComp c;
  ASSERT_FALSE(c.start(CompSide::Left, 1, 0, 1, core::Vec{}));
  std::vector<Instruction> out;
  EXPECT_TRUE(c.push(Instruction{{0, 3, 1}, Linear{xyz(0.5, 0), 10}}, out));
  EXPECT_FALSE(c.push(Instruction{{0, 4, 1}, Linear{xyz(10, 0), 10}}, out));
  c.stop(out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_TRUE(at_xy(std::get<Linear>(out[0].op).end, 10, 1));
  EXPECT_TRUE(at_xy(c.tool_position(), 10, 1));
}

// LinuxCNC (arc_not_allowed): after G40 ends a compensation that moved, the next move must be
// straight; its start is the tool position, not the programmed point the centre words count from.
// rs274 -g: "The move just after exiting cutter compensation mode must be straight, not an arc" for
// "G40 G2 X30 Y30 I5 J5" and for a G2 on the line after G40; after a G0 (even Z only) arcs are fine
// again: ARC_FEED(40, 30, 35, 30, -1, ..) below.
TEST(IsoCutterComp, TheMoveAfterG40MustBeStraight) {
  const std::string body = "G21 G90 G17 F300\nG0 X-10 Y-10\nG41.1 D2 G1 X0 Y0\nG1 X20\nG1 Y20\n";
  EXPECT_EQ(one_error(body + "G40 G2 X30 Y30 I5 J5\n"),
            "t.ngc:6:5: error: the move just after G40 must be straight, not an arc: it starts where the tool is, not "
            "at the programmed point (LinuxCNC)");
  EXPECT_EQ(one_error(body + "G40\nG2 X30 Y30 I5 J5\n").rfind("t.ngc:7:1: error: the move just after G40", 0), 0u);
  const auto p = parse_ok(body + "G40\nG0 Z5\nG0 X30 Y30\nG2 X40 Y30 I5 J0\n");
  const auto m = motions(p.instructions);
  ASSERT_FALSE(m.empty());
  const auto& a = std::get<Arc>(m.back().op);
  EXPECT_TRUE(at_xy(a.end, 40, 30));
  EXPECT_NEAR(a.center0, 35, kTol);
  EXPECT_NEAR(a.center1, 30, kTol);
  // Compensation switched on and off without a move leaves arcs allowed, as in LinuxCNC.
  parse_ok("G21 G90 G17 F300\nG0 X0 Y0\nG41.1 D2\nG40\nG2 X10 Y0 I5 J0\n");
}

// LinuxCNC refuses offset changes that move the programmed path under compensation: rs274 -g says
// "Cannot change axis offsets with cutter radius comp" for G92, "Cannot change the active coordinate
// system with cutter radius compensation on" for G10 L2/L20 on the system in use, "Cannot change tool
// offset with cutter radius compensation on" for G43/G43.1/G49; G92.1 and G10 on another system pass.
TEST(IsoCutterComp, OffsetChangesAreRefusedWhileOn) {
  const std::string on = "G21 G90 G17 F300\nG0 X-10 Y-10\nG41.1 D2 G1 X0 Y0\n";
  const std::string off = "G1 X10\nG40\n";
  EXPECT_EQ(one_error(on + "G92 X5\n" + off),
            "t.ngc:4:1: error: G92 cannot change the axis offsets with cutter radius compensation on (G40 first)");
  EXPECT_EQ(one_error(on + "G10 L2 P0 X5\n" + off),
            "t.ngc:4:1: error: cannot change the active coordinate system with cutter radius compensation on (G40 first)");
  EXPECT_EQ(one_error(on + "G10 L20 P1 X5\n" + off).rfind("t.ngc:4:1: error: cannot change the active coordinate system", 0), 0u);
  EXPECT_EQ(one_error(on + "G43.1 Z1\n" + off),
            "t.ngc:4:1: error: cannot change the tool length offset with cutter radius compensation on (G40 first)");
  EXPECT_EQ(one_error(on + "G49\n" + off).rfind("t.ngc:4:1: error: cannot change the tool length offset", 0), 0u);
  parse_ok(on + "G92.1\nG10 L2 P2 X5\n" + off);
}

// A spline under compensation went through the stage uncompensated, held back as if it were not a
// move, and the next corner was worked out from before it. LinuxCNC refuses it (rs274 -g: "Cannot
// convert spline with cutter radius compensation").
TEST(IsoCutterComp, SplinesAreRefusedWhileOn) {
  const std::string on = "G21 G90 G17 F300\nG0 X-10 Y-10\nG41.1 D2 G1 X0 Y0\n";
  const std::string want = "error: splines (G5, G5.1, G5.2) cannot run with cutter radius compensation on (G40 first)";
  EXPECT_EQ(one_error(on + "G5.1 X20 Y5 I5 J5\nG1 X30\nG40\n"), "t.ngc:4:1: " + want);
  EXPECT_EQ(one_error(on + "G5 X20 Y5 I5 J5 P-5 Q5\nG1 X30\nG40\n"), "t.ngc:4:1: " + want);
  EXPECT_EQ(parse_errors(on + "G5.2 X1 Y1 P1\nX2 Y2 P1\nX3 Y1 P1\nG5.3\nG40\n").at(0), "t.ngc:4:1: " + want);
}
