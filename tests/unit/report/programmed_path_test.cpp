// The programmed path the reports measure against: its deviation search (a start at the last
// nearest move, then ball bounds) finds what trying every move finds.
#include "report/programmed_path.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "control/path.hpp"
#include "program/iso/parser.hpp"

using namespace softmc;

namespace {
// A G5.2 spiral of `n` control points: one instruction of many NURBS pieces, turn upon turn close
// together, between two lines.
program::Program spiral(int n) {
  std::string text = "G21 G90 G64 P0.05\nG0 X310 Y200\nG1 X310 Y200.5 F3000\nG5.2 X310 Y200 L4 P1\n";
  for (int i = 1; i < n; ++i) {
    const double a = i * 0.05, r = 10 + 0.02 * i;
    text += "X" + std::to_string(300 + r * std::cos(a)) + " Y" + std::to_string(200 + r * std::sin(a)) + " P1\n";
  }
  text += "G5.3\nG1 X400 Y260\nM30\n";
  auto r = program::iso::parse(text, "spiral.ngc");
  EXPECT_TRUE(r.program) << (r.diagnostics.empty() ? "" : r.diagnostics.front().format());
  return r.program ? *r.program : program::Program{};
}

// Every move the search may use tried: those of the instruction and one on either side, and
// further the moves starting within kReach_mm of path before it or after it (at most kReachMoves
// more each way): the definition the search must meet.
double brute_force(const report::ProgrammedPath& pp, const core::Vec& p, std::uint32_t tag) {
  const std::size_t first = *pp.move_of(tag);
  std::size_t last = first;
  while (last + 1 < pp.moves.size() && pp.moves[last + 1].instruction <= tag) ++last;
  std::vector<double> along{0};
  for (const auto& m : pp.moves) along.push_back(along.back() + m.length);
  const auto reach = report::ProgrammedPath::kReach_mm;
  const auto most = report::ProgrammedPath::kReachMoves;
  double d = std::numeric_limits<double>::infinity();
  for (std::size_t m = 0; m < pp.moves.size(); ++m) {
    const bool near = m + 1 >= first && m <= last + 1;
    const bool before = m + 1 < first && first - 1 - m <= most && along[m] >= along[first] - reach;
    const bool after = m > last + 1 && m - last - 1 <= most && along[m] < along[last + 1] + reach;
    if (near || before || after) d = std::min(d, pp.segment(pp.moves[m]).distance_to(p, 0));
  }
  return d;
}
}  // namespace

TEST(ProgrammedPath, DeviationSearchFindsWhatTryingEveryMoveFinds) {
  const auto prog = spiral(200);
  const auto pp = report::programmed_path(prog);
  std::uint32_t nurbs = 0;
  for (std::uint32_t i = 0; i < prog.instructions.size(); ++i)
    if (std::holds_alternative<program::Nurbs>(prog.instructions[i].op)) nurbs = i;
  ASSERT_GT(pp.moves.size(), 100u);  // the spiral is in many pieces
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> off(-0.3, 0.3);
  std::uniform_int_distribution<std::size_t> pick(0, pp.moves.size() - 1);
  // Points near the path, walked along it (as a trace does), then jumping anywhere.
  for (int k = 0; k < 600; ++k) {
    const std::size_t m = k < 300 ? k * pp.moves.size() / 300 : pick(rng);
    const auto& mv = pp.moves[m];
    core::Vec p = pp.segment(mv).point(mv.length * (k % 7) / 7.0);
    p[0] += off(rng);
    p[1] += off(rng);
    const auto tag = static_cast<std::uint32_t>(mv.instruction);
    const double want = brute_force(pp, p, tag);
    EXPECT_NEAR(pp.deviation_mm(p, tag, tag, true, 0), want, 1e-12) << k;
    // With `enough`: a value at or below it when the distance is, else the distance itself.
    const double got = pp.deviation_mm(p, tag, tag, true, 0.1);
    if (want <= 0.1) EXPECT_LE(got, 0.1) << k;
    else EXPECT_NEAR(got, want, 1e-12) << k;
  }
  EXPECT_GT(nurbs, 0u);
}

// Arcs whose end is off their circle run as slight spirals, along which the arc-length parameter
// is not the distance travelled: the boxes (not a ball of half the length, which overshoots there
// by micrometres) keep the search exact.
TEST(ProgrammedPath, DeviationSearchIsExactOnSpirals) {
  auto r = program::iso::parse("G21 G90\nG0 X0 Y0\nG2 X400.2 Y0 I200 J0 F3000\nG3 X800 Y0 I199.8 J0\n"
                               "G2 X1199.85 Y0 I200 J0\nM30\n",
                               "spiral.ngc");
  ASSERT_TRUE(r.program) << (r.diagnostics.empty() ? "" : r.diagnostics.front().format());
  const auto pp = report::programmed_path(*r.program);
  std::vector<std::size_t> arcs;
  for (std::size_t m = 0; m < pp.moves.size(); ++m)
    if (pp.segment(pp.moves[m]).kind == motion::SegmentKind::Arc) arcs.push_back(m);
  ASSERT_EQ(arcs.size(), 3u);
  for (const auto m : arcs) EXPECT_GT(std::abs(pp.segment(pp.moves[m]).dradius), 0.1);  // spirals indeed
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> off(-0.5, 0.5);
  for (int k = 0; k < 3000; ++k) {
    const auto& mv = pp.moves[arcs[(k / 7) % 3]];
    core::Vec p = pp.segment(mv).point(mv.length * ((k * 37) % 1000) / 1000.0);
    p[0] += off(rng);
    p[1] += off(rng);
    const auto tag = static_cast<std::uint32_t>(mv.instruction);
    EXPECT_NEAR(pp.deviation_mm(p, tag, tag, true, 0), brute_force(pp, p, tag), 1e-12) << k;
  }
}

// A line is kept as its end, not as a 1.3 kB Segment: its start (the move before's end), its
// distance (Segment::distance_to's to the last bit: the summaries' deviations depend on it) and its
// segment are the walk's own (control::visit_program_geometry, as the channel builds them).
TEST(ProgrammedPath, ALineKeptAsItsEndsMeasuresAsItsSegment) {
  auto r = program::iso::parse("G21 G90\nG0 X1 Y2 Z3\nG1 X40.5 Y-7.25 Z3 F600\nG1 X40.5 Y-7.25 Z3\nG1 X-3 Y5 Z9\n"
                               "G2 X10 Y5 I6.5 J0\nG1 X0.1 Y0.3 Z0.7\nM30\n", "lines.ngc");
  ASSERT_TRUE(r.program);
  const auto pp = report::programmed_path(*r.program);
  std::vector<motion::Segment> walk;
  control::visit_program_geometry(*r.program, [&](std::uint32_t, const motion::Segment& s) { walk.push_back(s); });
  ASSERT_EQ(walk.size(), pp.moves.size());
  std::mt19937_64 rng(28);
  std::uniform_real_distribution<double> u(-60, 60);
  int lines = 0, arcs = 0;
  for (std::size_t k = 0; k < pp.moves.size(); ++k) {
    const auto& m = pp.moves[k];
    const motion::Segment& want = walk[k];
    const motion::Segment seg = pp.segment(m);
    (m.line ? lines : arcs) += 1;
    EXPECT_EQ(want.kind == motion::SegmentKind::Line, m.line);
    EXPECT_EQ(seg.kind, want.kind);
    EXPECT_EQ(pp.start_of(m), want.start);
    EXPECT_EQ(seg.start, want.start);
    EXPECT_EQ(seg.end, want.end);
    EXPECT_EQ(seg.dir, want.dir);
    EXPECT_EQ(seg.length, want.length);
    for (int n = 0; n < 200; ++n) {
      core::Vec p;
      for (int i = 0; i < 3; ++i) p[static_cast<std::size_t>(i)] = u(rng);
      EXPECT_EQ(pp.distance(m, p), want.distance_to(p)) << m.instruction;
    }
  }
  EXPECT_EQ(lines, 5);  // the rapid, three lines and the zero-length one
  EXPECT_EQ(arcs, 1);
  EXPECT_EQ(pp.curves.size(), 1u);
}

// The moves' ends are kept on the axes the program uses only, widened when a later move first leaves
// zero on another: every end and start comes back as the walk's segments have them, to the bit (a
// −0 too), and an instruction's positions before and after are those ends.
TEST(ProgrammedPath, EndsKeptOnTheAxesUsedComeBackBitForBit) {
  auto r = program::iso::parse("G21 G90\nG0 X1\nG1 X2 F600\nG1 Y2\nG4 P1\nG1 Z-3\nG1 X0 Y0 Z0\nG1 X-0.0 Y0.5\nM30\n", "axes.ngc");
  ASSERT_TRUE(r.program);
  const auto pp = report::programmed_path(*r.program);
  std::vector<motion::Segment> walk;
  std::vector<std::uint32_t> of;
  control::visit_program_geometry(*r.program, [&](std::uint32_t i, const motion::Segment& s) {
    walk.push_back(s);
    of.push_back(i);
  });
  ASSERT_EQ(walk.size(), pp.moves.size());
  ASSERT_GE(walk.size(), 6u);
  const auto same = [](const core::Vec& a, const core::Vec& b) { return std::memcmp(&a, &b, sizeof a) == 0; };
  for (std::size_t k = 0; k < pp.moves.size(); ++k) {
    EXPECT_TRUE(same(pp.end_of(pp.moves[k]), walk[k].end)) << "move " << k;
    EXPECT_TRUE(same(pp.start_of(pp.moves[k]), walk[k].start)) << "move " << k;
    EXPECT_TRUE(same(pp.after(of[k]), walk[k].end)) << "move " << k;
    EXPECT_TRUE(same(pp.before(of[k]), walk[k].start)) << "move " << k;
    EXPECT_EQ(*pp.move_of(of[k]), k);
  }
  for (std::size_t i = 0; i < r.program->instructions.size(); ++i) {
    if (program::is_motion(r.program->instructions[i].op)) continue;
    EXPECT_FALSE(pp.move_of(i));
    EXPECT_TRUE(same(pp.before(i), pp.after(i)));
  }
}
