// SPC parser: every instruction and operand form (S-2..S-7), line numbering (S-1), load-time errors.
#include <gtest/gtest.h>

#include "program/spc/parser.hpp"
#include "program/spc/store.hpp"

namespace softmc::program::spc {
namespace {

SpcProgram ok(std::string_view text, ParseOptions opt = {}) {
  auto r = parse(text, "P1.spc", opt);
  for (const auto& d : r.diagnostics) ADD_FAILURE() << d.format();
  EXPECT_TRUE(r.program.has_value());
  return r.program ? *r.program : SpcProgram{};
}

// The first diagnostic, formatted.
std::string first_error(std::string_view text, ParseOptions opt = {}) {
  auto r = parse(text, "P1.spc", opt);
  EXPECT_FALSE(r.program.has_value());
  return r.diagnostics.empty() ? std::string("<none>") : r.diagnostics.front().format();
}

template <class T>
const T& only(const SpcProgram& p) {
  EXPECT_EQ(p.size(), 1u);
  return std::get<T>(p.ir.instructions.at(0).op);
}

TEST(Spc200, S2_MoveFormsAllOperands) {
  auto p = ok("N000 G02 G91 X200 FX0 Y@7 FY70 Z-100.5 FZ80 U600.25 FU0\n");
  const auto& m = only<SpcMove>(p);
  EXPECT_EQ(m.profile, SpcProfile::SineSquared);
  EXPECT_EQ(m.coord, SpcCoord::Relative);
  EXPECT_EQ(m.axes, 0b1111);
  EXPECT_EQ(m.target[0], (SpcPos{false, 20000, 0}));
  EXPECT_EQ(m.target[1], (SpcPos{true, 0, 7}));
  EXPECT_EQ(m.target[2].centi, -10050);
  EXPECT_EQ(m.target[3].centi, 60025);
  EXPECT_EQ(m.speed_pct[1], 70);
  EXPECT_EQ(m.speed_pct[2], 80);

  const auto r = only<SpcMove>(ok("N5 G00 G90 X300.5 Y@0"));
  EXPECT_EQ(r.profile, SpcProfile::Rapid);
  EXPECT_EQ(r.coord, SpcCoord::Absolute);
  EXPECT_EQ(r.target[0].centi, 30050);
  const auto g1 = only<SpcMove>(ok("n001 g01 x@10 fx50 ; lower case and a comment"));
  EXPECT_EQ(g1.profile, SpcProfile::Trapezoid);
  EXPECT_EQ(g1.coord, SpcCoord::Modal);
  EXPECT_TRUE(g1.target[0].is_reg);
  const auto packed = only<SpcMove>(ok("N000G01X10FX0"));
  EXPECT_EQ(packed.target[0].centi, 1000);
}

TEST(Spc200, S3_MotionSpecificationInstructions) {
  auto p = ok("N0 G08 X50 Y0\nN1 G09 Z99\nN2 G25 X10 Y20 Z50\nN3 G61 X1 U6\nN4 M37 X40\nN5 G04 100\n");
  ASSERT_EQ(p.size(), 6u);
  const auto& acc = std::get<SpcAxisSetting>(p.ir.instructions[0].op);
  EXPECT_EQ(acc.kind, SpcSetting::Accel);
  EXPECT_EQ(acc.axes, 0b11);
  EXPECT_EQ(acc.value[0], 50);
  EXPECT_EQ(std::get<SpcAxisSetting>(p.ir.instructions[1].op).kind, SpcSetting::Decel);
  const auto& pass = std::get<SpcAxisSetting>(p.ir.instructions[2].op);
  EXPECT_EQ(pass.kind, SpcSetting::PassThrough);
  EXPECT_EQ(pass.value[2], 50);
  const auto& mc = std::get<SpcAxisSetting>(p.ir.instructions[3].op);
  EXPECT_EQ(mc.kind, SpcSetting::MotionComplete);
  EXPECT_EQ(mc.value[3], 6);
  EXPECT_EQ(std::get<SpcAxisSetting>(p.ir.instructions[4].op).kind, SpcSetting::Mass);
  EXPECT_EQ(std::get<SpcDwell>(p.ir.instructions[5].op).hundredths, 100u);
}

TEST(Spc200, S4_FlowInstructionsResolveLiteralJumps) {
  auto p = ok("N000 E05 20\nN010 E05 R3\nN020 L12\nN021 LR7\nN022 M02\nN023 M30\nN024 M00\n");
  const auto& j = std::get<SpcJump>(p.ir.instructions[0].op);
  EXPECT_FALSE(j.via_reg);
  EXPECT_EQ(j.line, 20);
  EXPECT_EQ(j.index, 2);  // N020 is the third instruction
  const auto& jr = std::get<SpcJump>(p.ir.instructions[1].op);
  EXPECT_TRUE(jr.via_reg);
  EXPECT_EQ(jr.reg, 3);
  EXPECT_EQ(std::get<SpcCall>(p.ir.instructions[2].op).program, 12);
  EXPECT_TRUE(std::get<SpcCall>(p.ir.instructions[3].op).via_reg);
  EXPECT_TRUE(std::holds_alternative<SpcReturn>(p.ir.instructions[4].op));
  EXPECT_TRUE(std::holds_alternative<SpcEnd>(p.ir.instructions[5].op));
  EXPECT_TRUE(std::holds_alternative<SpcSync>(p.ir.instructions[6].op));
  EXPECT_EQ(p.index(21), 3);
  EXPECT_EQ(p.index(11), -1);
}

TEST(Spc200, S5_RegisterInstructions) {
  auto p = ok("N300 G28 @10 X0 Y0 Z0 U0\nN301 G29 @90 X@10\nN302 M38 @5 X Y\nN303 #LR5=-32767\nN304 #AR5=12\n"
              "N305 #TR5=-3 303\n");
  const auto& g28 = std::get<SpcPosReg>(p.ir.instructions[0].op);
  EXPECT_EQ(g28.op, SpcPosRegOp::Load);
  EXPECT_EQ(g28.reg, 10);
  EXPECT_EQ(g28.axes, 0b1111);
  const auto& g29 = std::get<SpcPosReg>(p.ir.instructions[1].op);
  EXPECT_EQ(g29.op, SpcPosRegOp::Add);
  EXPECT_TRUE(g29.value[0].is_reg);
  const auto& m38 = std::get<SpcPosReg>(p.ir.instructions[2].op);
  EXPECT_EQ(m38.op, SpcPosRegOp::Capture);
  EXPECT_EQ(m38.axes, 0b11);
  EXPECT_EQ(std::get<SpcIntReg>(p.ir.instructions[3].op).value, -32767);
  EXPECT_EQ(std::get<SpcIntReg>(p.ir.instructions[4].op).op, SpcIntRegOp::Add);
  const auto& tr = std::get<SpcIntReg>(p.ir.instructions[5].op);
  EXPECT_EQ(tr.op, SpcIntRegOp::Test);
  EXPECT_EQ(tr.value, -3);
  EXPECT_EQ(tr.index, 3);
}

TEST(Spc200, S6_IoInstructionsEveryForm) {
  auto p = ok("N100 #TI1.15 105\nN101 #TNI0.0 101\nN102 #TF63 100\nN103 #TNF0 100\nN104 #TQ3.15 100\n"
              "N105 #TNQ0.7 100\nN106 #SQ0.2\nN107 #RQ5.7\nN108 #SF1\nN109 #RF2\n");
  const auto& ti = std::get<SpcBitTest>(p.ir.instructions[0].op);
  EXPECT_EQ(ti.bit.space, SpcBitSpace::Input);
  EXPECT_EQ(ti.bit.module, 1);
  EXPECT_EQ(ti.bit.bit, 15);
  EXPECT_TRUE(ti.jump_when);
  EXPECT_EQ(ti.index, 5);
  const auto& wait = std::get<SpcBitTest>(p.ir.instructions[1].op);
  EXPECT_FALSE(wait.jump_when);
  EXPECT_EQ(wait.index, 1);  // its own line: a wait
  EXPECT_EQ(std::get<SpcBitTest>(p.ir.instructions[2].op).bit.space, SpcBitSpace::Flag);
  EXPECT_EQ(std::get<SpcBitTest>(p.ir.instructions[4].op).bit.space, SpcBitSpace::Output);
  const auto& sq = std::get<SpcBitWrite>(p.ir.instructions[6].op);
  EXPECT_TRUE(sq.value);
  EXPECT_EQ(sq.bit.bit, 2);
  EXPECT_FALSE(std::get<SpcBitWrite>(p.ir.instructions[7].op).value);
  EXPECT_EQ(std::get<SpcBitWrite>(p.ir.instructions[8].op).bit.space, SpcBitSpace::Flag);
}

TEST(Spc200, S1_BlankAndCommentLinesAndDump) {
  auto p = ok("; program 1\n\nN000 G00 X10 ; go\n   \nN001 M30\n");
  ASSERT_EQ(p.size(), 2u);
  EXPECT_EQ(p.ir.instructions[0].loc.line, 3u);
  EXPECT_EQ(p.ir.instructions[0].loc.col, 6u);
  EXPECT_EQ(dump(p.ir), "start X0.000000 Y0.000000 Z0.000000\n    3:6   spc move G00 X10.00\n    5:6   spc end\n");
}

struct ErrorCase {
  const char* text;
  const char* expected;  // the first diagnostic
};

TEST(Spc200, S1_S6_LoadTimeErrorsWithLineAndColumn) {
  const ErrorCase cases[] = {
      {"N005 G00 X1\nN005 G00 X2", "P1.spc:2:1: error: line number N005 after N005: line numbers must increase strictly"},
      {"N005 G00 X1\nN004 G00 X2", "P1.spc:2:1: error: line number N004 after N005: line numbers must increase strictly"},
      {"N1000 M30", "P1.spc:1:2: error: line number 1000 out of range 0..999"},
      {"G00 X1", "P1.spc:1:1: error: a line starts with its number N000..N999"},
      {"N000 G01 X10 FX100", "P1.spc:1:16: error: speed % 100 out of range 0..99"},
      {"N000 G01 X10", "P1.spc:1:13: error: expected FX <speed %> after the X target"},
      {"N000 G00 X10 FX5", "P1.spc:1:14: error: G00 moves at the highest speed: no F word"},
      {"N000 G00 X1 X2", "P1.spc:1:13: error: axis X given twice"},
      {"N000 G00 A1", "P1.spc:1:10: error: expected an axis X, Y, Z or U"},
      {"N000 G00", "P1.spc:1:9: error: a motion line names one to four axes"},
      {"N000 G00 X@100", "P1.spc:1:12: error: position register 100 out of range 0..99"},
      {"N000 G00 X10000", "P1.spc:1:11: error: position out of range -9999.99..9999.99"},
      {"N000 G00 X1.234", "P1.spc:1:11: error: a position has at most two decimals"},
      {"N000 G61 X7", "P1.spc:1:11: error: G61 condition 7 out of range 1..6"},
      {"N000 G08 X100", "P1.spc:1:11: error: percentage 100 out of range 0..99"},
      {"N000 G07 X1", "P1.spc:1:6: error: unknown instruction G07"},
      {"N000 E05 7", "P1.spc:1:10: error: jump to line N007, which this program does not have"},
      {"N000 #TNI0.0 9", "P1.spc:1:14: error: jump to line N009, which this program does not have"},
      {"N000 #TI0.10 0", "P1.spc:1:9: error: I0.10 is not an address of the SPC200 I/O (S-6)"},
      {"N000 #TI6.0 0", "P1.spc:1:9: error: I6.0 is not an address of the SPC200 I/O (S-6)"},
      {"N000 #SQ0.8", "P1.spc:1:9: error: Q0.8 is not an address of the SPC200 I/O (S-6)"},
      {"N000 #SQ1.16", "P1.spc:1:9: error: Q1.16 is not an address of the SPC200 I/O (S-6)"},
      {"N000 #SQ0.3", "P1.spc:1:9: error: Q0.3 is a system output (S-8, S-9): a program must not write it"},
      {"N000 #RQ0.7", "P1.spc:1:9: error: Q0.7 is a system output (S-8, S-9): a program must not write it"},
      {"N000 #SF64", "P1.spc:1:9: error: flag 64 out of range 0..63"},
      {"N000 #LR100=1", "P1.spc:1:9: error: register 100 out of range 0..99"},
      {"N000 #AR1=32768", "P1.spc:1:11: error: value 32768 out of range -32767..32767"},
      {"N000 L100", "P1.spc:1:7: error: program number 100 out of range 0..99"},
      {"N000 M30 X", "P1.spc:1:10: error: unexpected text after the instruction"},
      {"N000", "P1.spc:1:5: error: expected an instruction after the line number"},
      {"N000 G28 X1", "P1.spc:1:10: error: expected the position register @i"},
  };
  for (const auto& c : cases) EXPECT_EQ(first_error(c.text), c.expected) << c.text;
}

TEST(Spc200, S1_EveryErrorOfAFileIsReported) {
  auto r = parse("N000 G07\nN001 G00 X1\nN001 M30\nN002 #SQ0.5\n", "P3.spc");
  ASSERT_EQ(r.diagnostics.size(), 3u);
  EXPECT_EQ(r.diagnostics[0].line, 1u);
  EXPECT_EQ(r.diagnostics[1].line, 3u);
  EXPECT_EQ(r.diagnostics[2].line, 4u);
}

TEST(Spc200, S9_RecordSelectProgramsHoldOnlyMotionLinesUpToN031) {
  ParseOptions rs{true, 1};
  ok("N000 G01 X10 FX0\nN001 G08 X50\nN002 G61 X2\nN031 G00 X0\n", rs);
  EXPECT_EQ(first_error("N032 G00 X1", rs), "P1.spc:1:1: error: line N032 in a Record Select program: at most N000..N031 (S-9)");
  EXPECT_EQ(first_error("N000 #SQ0.0", rs),
            "P1.spc:1:6: error: a Record Select program holds only motion and motion-specification instructions (S-9)");
  EXPECT_EQ(first_error("N000 E05 0", rs),
            "P1.spc:1:6: error: a Record Select program holds only motion and motion-specification instructions (S-9)");
  // The same lines are fine in Start/Stop mode.
  ok("N040 #SQ0.0\n");
}

TEST(Spc200, S4_StoreChecksCallsAcrossPrograms) {
  ProgramStore store;
  core::Diagnostics d;
  ASSERT_TRUE(store.add(1, "N000 L2\nN001 L3\nN002 M30\n", "P1.spc", {}, d));
  ASSERT_TRUE(store.add(2, "N000 M02\n", "P2.spc", {}, d));
  auto v = store.validate();
  ASSERT_EQ(v.size(), 1u);
  EXPECT_EQ(v[0].format(), "P1.spc:2:6: error: call of program P3, which is empty or missing (S-4)");
  EXPECT_EQ(program_number_from_file_name("P12.spc"), 12);
  EXPECT_EQ(program_number_from_file_name("p0.SPC"), 0);
  EXPECT_EQ(program_number_from_file_name("P100.spc"), -1);
  EXPECT_EQ(program_number_from_file_name("main.spc"), -1);
}

}  // namespace
}  // namespace softmc::program::spc
