// Work limits, streaming and the per-block state handling that keep any input cheap (parser.hpp).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "iso_test_util.hpp"

using namespace softmc;
using namespace softmc::program;
using namespace softmc::program::iso::test;

// A canned cycle with a huge repeat count stops at the instruction budget instead of running on
// (a libFuzzer input made 300 000 moves from one line before).
TEST(IsoLimits, CannedCycleRepeatsStopAtTheInstructionBudget) {
  iso::ParseOptions opt;
  opt.max_instructions = 1000;
  const auto e = parse_errors("G21 G90 F100\nG0 Z5\nG81 X1 Y1 Z-1 R1 L100000\nM30\n", opt);
  ASSERT_EQ(e.size(), 1u);
  EXPECT_NE(e[0].find("t.ngc:3:"), std::string::npos) << e[0];
  EXPECT_NE(e[0].find("the canned cycle makes more than"), std::string::npos) << e[0];
  // Pecks count as well.
  EXPECT_FALSE(iso::parse("G21 G90 F100\nG0 Z5\nG83 X1 Y1 Z-100 R1 Q0.01\nM30\n", "t.ngc", opt).program);
  // The same cycle with a few repeats is fine.
  EXPECT_TRUE(iso::parse("G21 G90 F100\nG0 Z5\nG81 X1 Y1 Z-1 R1 L10\nM30\n", "t.ngc", opt).program);
}

// A loop that makes instructions without end stops at the budget, with the line of the loop body.
TEST(IsoLimits, InstructionBudgetStopsAnEndlessLoop) {
  iso::ParseOptions opt;
  opt.max_instructions = 500;
  const auto e = parse_errors("G21 F100\no1 repeat [1000]\nG1 X1\nG1 X2\no1 endrepeat\nM30\n", opt);
  ASSERT_EQ(e.size(), 1u);
  EXPECT_NE(e[0].find("makes more than"), std::string::npos) << e[0];
}

// The budgets grow with the text: a long straight program never hits them, however small they are.
TEST(IsoLimits, BudgetsGrowWithTheLengthOfTheProgram) {
  std::string text = "G21 G90 F600\n";
  for (int i = 0; i < 20000; ++i) text += "G1 X" + std::to_string(i % 100) + " Y" + std::to_string(i % 7) + "\n";
  text += "M30\n";
  iso::ParseOptions opt;
  opt.max_blocks = 10;
  opt.max_instructions = 10;
  const auto p = parse_ok(text, opt);
  EXPECT_GT(p.instructions.size(), 19000u);
}

// An error inside a G5.2 block leaves the control points collected so far (they move into the
// block's working state rather than being copied, and move back on error).
TEST(IsoLimits, NurbsPointsSurviveAnErrorInsideTheBlock) {
  const std::string head = "G21 G90 G17 F600\nG0 X0 Y0\nG5.2 X10 Y0 L3\nX10 Y10\n";
  const auto r = iso::parse(head + "X20 Y10 Q3\nX20 Y20\nG5.3\nM30\n", "t.ngc");
  ASSERT_FALSE(r.program);
  ASSERT_EQ(r.diagnostics.size(), 1u) << r.diagnostics[0].format();
  EXPECT_EQ(r.diagnostics[0].line, 5u);
  // Without the bad line the same NURBS has the start point and three more.
  const auto p = parse_ok(head + "X20 Y20\nG5.3\nM30\n");
  std::size_t found = 0;
  for (const auto& ins : p.instructions)
    if (const auto* n = std::get_if<Nurbs>(&ins.op)) {
      EXPECT_EQ(n->ctrl.size(), 4u);
      ++found;
    }
  EXPECT_EQ(found, 1u);
  // A failing G5.3 (a stray word after it) keeps the points too: the block can be closed later.
  const auto q = iso::parse(head + "G5.3 Q1\nG5.3\nM30\n", "t.ngc");
  ASSERT_FALSE(q.program);
  EXPECT_EQ(q.diagnostics.size(), 1u);
}

// #5420… (current position) are brought up to date only when a line reads a parameter, and read
// the same as when they were written after every block.
TEST(IsoLimits, PositionParametersAreCurrentWhenRead) {
  iso::ParseOptions opt;
  opt.start = xyz(1, 2, 3);
  const auto p = parse_ok("G21 G90 F600\nG1 X[#5420 + 10] Y[#5421]\nG1 X5 Y6\nG0 X[#5420 * 2] Y[#5421 * 2] Z[#5422]\nM30\n", opt);
  EXPECT_DOUBLE_EQ(op_at<Linear>(p, 0).end[0], 11);
  EXPECT_DOUBLE_EQ(op_at<Linear>(p, 0).end[1], 2);
  EXPECT_DOUBLE_EQ(op_at<Rapid>(p, 2).end[0], 10);
  EXPECT_DOUBLE_EQ(op_at<Rapid>(p, 2).end[1], 12);
  EXPECT_DOUBLE_EQ(op_at<Rapid>(p, 2).end[2], 3);
}

// Streaming: the sink sees every instruction, in order, in batches; the result keeps none.
TEST(IsoLimits, SinkSeesTheSameInstructionsInBatches) {
  std::string text = "G21 G90 F600\n";
  for (int i = 0; i < 1000; ++i) text += "G1 X" + std::to_string(i) + "\nG3 X" + std::to_string(i) + " Y1 J0.5\nG1 Y0\n";
  text += "M30\n";
  const auto whole = parse_ok(text);
  iso::ParseOptions opt;
  opt.sink_batch = 100;
  std::vector<Instruction> got;
  std::size_t batches = 0;
  opt.sink = [&](const Program& b) {
    ++batches;
    EXPECT_LE(b.instructions.size(), 110u);
    got.insert(got.end(), b.instructions.begin(), b.instructions.end());
  };
  const auto r = iso::parse(text, "t.ngc", opt);
  ASSERT_TRUE(r.program);
  EXPECT_TRUE(r.program->instructions.empty());
  EXPECT_GT(batches, 20u);
  Program streamed = *r.program;
  streamed.instructions = got;
  EXPECT_EQ(dump(streamed), dump(whole));
}
