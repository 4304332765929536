// ISO language: expressions, parameters, O-word control flow, subroutine files, messages, limits.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "iso_test_util.hpp"
#include "program/iso/lexer.hpp"

using namespace softmc;
using namespace softmc::program;
using namespace softmc::program::iso::test;

namespace {

// X of every rapid, in order: the programs below report values by moving X.
std::vector<double> rapid_x(const Program& p) {
  std::vector<double> out;
  for (const auto& i : p.instructions)
    if (const auto* r = std::get_if<Rapid>(&i.op)) out.push_back(r->end[0]);
  return out;
}

double value_of(const std::string& expr) {
  const auto p = parse_ok("G0 X" + expr + "\n");
  const auto x = rapid_x(p);
  return x.empty() ? NAN : x[0];
}

}  // namespace

TEST(IsoExpressions, OperatorPrecedenceAsLinuxCnc) {
  EXPECT_DOUBLE_EQ(value_of("[2 + 3 * 4]"), 14);
  EXPECT_DOUBLE_EQ(value_of("[[2 + 3] * 4]"), 20);
  EXPECT_DOUBLE_EQ(value_of("[2 ** 3 ** 2]"), 64);  // left-associative, as LinuxCNC
  EXPECT_DOUBLE_EQ(value_of("[2 * 3 ** 2]"), 18);
  EXPECT_DOUBLE_EQ(value_of("[10 - 4 - 3]"), 3);
  EXPECT_DOUBLE_EQ(value_of("[12 / 4 / 3]"), 1);
  EXPECT_DOUBLE_EQ(value_of("[7 MOD 3]"), 1);
  EXPECT_DOUBLE_EQ(value_of("[-7 MOD 3]"), 2);  // 0 <= r < |b|
  EXPECT_DOUBLE_EQ(value_of("[1 + 2 GT 2]"), 1);  // + binds tighter than GT
  EXPECT_DOUBLE_EQ(value_of("[1 LT 2 AND 3 LT 2]"), 0);
  EXPECT_DOUBLE_EQ(value_of("[1 LT 2 OR 3 LT 2]"), 1);
  EXPECT_DOUBLE_EQ(value_of("[1 XOR 1]"), 0);
  EXPECT_DOUBLE_EQ(value_of("[1 EQ 1.00001]"), 1);  // LinuxCNC's EQ tolerance 0.0001
  EXPECT_DOUBLE_EQ(value_of("[1 NE 1.001]"), 1);
  EXPECT_DOUBLE_EQ(value_of("[2 GE 2]"), 1);
  EXPECT_DOUBLE_EQ(value_of("[2 LE 1]"), 0);
  EXPECT_DOUBLE_EQ(value_of("-[2 + 1]"), -3);
  EXPECT_DOUBLE_EQ(value_of("[-[2]*-3]"), 6);
}

TEST(IsoExpressions, FunctionsInDegrees) {
  EXPECT_NEAR(value_of("SIN[30]"), 0.5, 1e-12);
  EXPECT_NEAR(value_of("cos[60]"), 0.5, 1e-12);
  EXPECT_NEAR(value_of("TAN[45]"), 1, 1e-12);
  EXPECT_NEAR(value_of("ATAN[1]/[1]"), 45, 1e-12);
  EXPECT_NEAR(value_of("ATAN[1]/[-1]"), 135, 1e-12);
  EXPECT_NEAR(value_of("ASIN[0.5]"), 30, 1e-12);
  EXPECT_NEAR(value_of("ACOS[0.5]"), 60, 1e-12);
  EXPECT_DOUBLE_EQ(value_of("SQRT[16]"), 4);
  EXPECT_DOUBLE_EQ(value_of("ABS[-3]"), 3);
  EXPECT_DOUBLE_EQ(value_of("FIX[-2.5]"), -3);
  EXPECT_DOUBLE_EQ(value_of("FUP[2.1]"), 3);
  EXPECT_DOUBLE_EQ(value_of("ROUND[2.5]"), 3);
  EXPECT_DOUBLE_EQ(value_of("ROUND[-2.5]"), -3);
  EXPECT_NEAR(value_of("LN[EXP[2]]"), 2, 1e-12);
  EXPECT_DOUBLE_EQ(value_of("EXISTS[#<nope>]"), 0);
  EXPECT_DOUBLE_EQ(parse_ok("#<yes> = 1\nG0 X EXISTS[#<yes>]\n").instructions.size(), 1);
}

TEST(IsoExpressions, ErrorsPointAtTheOperatorOrFunction) {
  EXPECT_EQ(one_error("G0 X[1 / 0]\n"), "t.ngc:1:8: error: division by zero");
  EXPECT_EQ(one_error("G0 X[1 MOD 0]\n"), "t.ngc:1:8: error: modulo by zero");
  EXPECT_EQ(one_error("G0 XSQRT[-1]\n"), "t.ngc:1:5: error: SQRT of the negative number -1");
  EXPECT_EQ(one_error("G0 X LN[0]\n"), "t.ngc:1:6: error: LN of 0: the argument must be greater than zero");
  EXPECT_EQ(one_error("G0 X ASIN[2]\n"), "t.ngc:1:6: error: ASIN argument 2 outside -1 … 1");
  EXPECT_EQ(one_error("G0 X[-2 ** 0.5]\n"), "t.ngc:1:9: error: negative number raised to a non-integer power");
  EXPECT_EQ(one_error("G0 X[1 + 2\n"), "t.ngc:1:5: error: '[' has no closing ']'");
  EXPECT_EQ(one_error("G0 X[1 @ 2]\n"), "t.ngc:1:8: error: unknown operator '@' in expression");
  EXPECT_EQ(one_error("G0 X FOO[1]\n"), "t.ngc:1:6: error: unknown function or word 'foo' in a value");
  EXPECT_EQ(one_error("G0 X ATAN[1]\n"), "t.ngc:1:6: error: ATAN needs two arguments: ATAN[y]/[x]");
}

TEST(IsoExpressions, HugeAndNanProducingValuesAreErrors) {
  EXPECT_EQ(one_error("G0 X[999999999 * 999999999 * 999999999 ** 40]\n"),
            "t.ngc:1:40: error: expression result is not a finite number");
  EXPECT_EQ(one_error("G0 X EXP[1000]\n"), "t.ngc:1:6: error: expression result is not a finite number");
  std::string deep = "G0 X";
  for (int i = 0; i < 500; ++i) deep += '[';
  deep += '1';
  for (int i = 0; i < 500; ++i) deep += ']';
  EXPECT_NE(one_error(deep + "\n").find("expression nested too deeply"), std::string::npos);
}

TEST(IsoParameters, NumberedNamedAndIndirect) {
  const auto p = parse_ok(
      "#1 = 5\n"
      "#2 = [#1 * 2]\n"
      "#<len> = [#2 + 1]\n"
      "#<_glob> = 7\n"
      "#[#1 + 1] = 3\n"  // #6 = 3
      "##1 = 9\n"         // #5 = 9
      "G0 X#2\nG0 X#<len>\nG0 X#<_glob>\nG0 X#6\nG0 X#5\nG0 X#<L E N>\n");
  EXPECT_EQ(rapid_x(p), (std::vector<double>{10, 11, 7, 3, 9, 11}));
}

TEST(IsoParameters, ValuesOfALineAreReadBeforeItsAssignments) {
  // LinuxCNC: "#1=2 #2=#1" sets #2 to the value #1 had before the line.
  const auto p = parse_ok("#1 = 1\n#1 = 2 #2 = #1\nG0 X#2\n");
  EXPECT_EQ(rapid_x(p), (std::vector<double>{1}));
}

TEST(IsoParameters, UndefinedNamedAndOutOfRangeAreErrors) {
  EXPECT_EQ(one_error("G0 X#<nothing>\n"), "t.ngc:1:5: error: named parameter #<nothing> is not defined");
  EXPECT_EQ(one_error("G0 X#6000\n"), "t.ngc:1:5: error: parameter #6000 does not exist (#1 … #5602)");
  EXPECT_EQ(one_error("#5420 = 1\n"), "t.ngc:1:1: error: parameter #5420 is read-only");
  // LinuxCNC's read-only ones are #5400…#5413 and #5420…#5428 (rs274 -g: "Parameter is readonly");
  // the others up to #5602 may be written (offsets.ngc of LinuxCNC's examples starts with #5599 = 1).
  EXPECT_EQ(one_error("#5413 = 1\n"), "t.ngc:1:1: error: parameter #5413 is read-only");
  EXPECT_EQ(one_error("#5428 = 1\n"), "t.ngc:1:1: error: parameter #5428 is read-only");
  parse_ok("#5399 = 1\n#5414 = 1\n#5419 = 1\n#5429 = 1\n#5599 = 1\n#5602 = 1\n");
  EXPECT_EQ(one_error("G0 X#1.5\n"), "t.ngc:1:5: error: parameter number 1.5 is not a whole number");
}

TEST(IsoParameters, StandardParametersFollowTheState) {
  // #5420… is the current position in program coordinates; #5221… the G54 offsets.
  const auto p = parse_ok("G10 L2 P1 X100\nG0 X5 Y6\nG0 X#5420 Y#5421\nG0 X#5221\n");
  const auto x = rapid_x(p);
  ASSERT_EQ(x.size(), 3u);
  EXPECT_DOUBLE_EQ(x[1], 105);  // X5 again, in G54
  EXPECT_DOUBLE_EQ(x[2], 200);  // X100 in G54
}

TEST(IsoControlFlow, IfElseIfElse) {
  const char* kProg =
      "o1 if [#1 EQ 1]\n G0 X1\n"
      "o1 elseif [#1 EQ 2]\n G0 X2\n"
      "o1 else\n G0 X3\n"
      "o1 endif\n";
  EXPECT_EQ(rapid_x(parse_ok(std::string("#1=1\n") + kProg)), (std::vector<double>{1}));
  EXPECT_EQ(rapid_x(parse_ok(std::string("#1=2\n") + kProg)), (std::vector<double>{2}));
  EXPECT_EQ(rapid_x(parse_ok(std::string("#1=7\n") + kProg)), (std::vector<double>{3}));
}

TEST(IsoControlFlow, WhileDoRepeatBreakContinue) {
  EXPECT_EQ(rapid_x(parse_ok("#1=0\no10 while [#1 LT 3]\nG0 X#1\n#1=[#1+1]\no10 endwhile\n")),
            (std::vector<double>{0, 1, 2}));
  EXPECT_EQ(rapid_x(parse_ok("#1=5\no11 do\nG0 X#1\n#1=[#1+1]\no11 while [#1 LT 3]\n")),
            (std::vector<double>{5}));  // a do-loop runs once at least
  EXPECT_EQ(rapid_x(parse_ok("#1=0\no12 repeat [3]\n#1=[#1+2]\nG0 X#1\no12 endrepeat\n")),
            (std::vector<double>{2, 4, 6}));
  EXPECT_EQ(rapid_x(parse_ok("#1=0\no13 while [1]\n#1=[#1+1]\no14 if [#1 EQ 2]\no13 continue\no14 endif\n"
                             "o15 if [#1 GT 4]\no13 break\no15 endif\nG0 X#1\no13 endwhile\nG0 X99\n")),
            (std::vector<double>{1, 3, 4, 99}));
  EXPECT_TRUE(rapid_x(parse_ok("o16 repeat [0]\nG0 X1\no16 endrepeat\n")).empty());
}

TEST(IsoControlFlow, ABareOWordIsAProgramNumber) {
  // LinuxCNC 2.9 reads "O0001" (or "o<name>") alone on its line as a Fanuc-style program number and
  // goes on: rs274 -g runs "O0001 / G21 F100 / G1 X1" as STRAIGHT_FEED(1, ..), also with "N5 O0001",
  // a comment after it, or in the middle of the program. With anything else after it, it is an error.
  EXPECT_EQ(rapid_x(parse_ok("%\nO0001 (PART 7)\nG0 X1\nN5 O0002\no<name>\nG0 X2\n%\n")), (std::vector<double>{1, 2}));
  EXPECT_EQ(one_error("O0001 G21\n"), "t.ngc:1:1: error: unknown O-word keyword 'g'");
}

TEST(IsoControlFlow, RepeatRoundsItsCountToTheNearestWholeNumber) {
  // LinuxCNC: repeat_count = round_to_int(value) (nearbyint: halves to even), nothing for 0 or less.
  // rs274 -g makes 2 moves for repeat [2.4] and [2.5], 3 for [2.6], 1 for [1.0001], none for [0.5] and
  // [-1] (a count computed as depth / step need not be whole).
  auto count = [](const std::string& n) {
    return rapid_x(parse_ok("o1 repeat [" + n + "]\nG91 G0 X1\no1 endrepeat\n")).size();
  };
  EXPECT_EQ(count("2.4"), 2u);
  EXPECT_EQ(count("2.5"), 2u);
  EXPECT_EQ(count("2.6"), 3u);
  EXPECT_EQ(count("1.0001"), 1u);
  EXPECT_EQ(count("0.5"), 0u);
  EXPECT_EQ(count("-1"), 0u);
}

TEST(IsoControlFlow, SubroutinesWithArgumentsLocalsAndReturnValue) {
  const auto p = parse_ok(
      "o<square> sub\n"
      "  #<half> = [#1 / 2]\n"
      "  G0 X#<half>\n"
      "  o<square> return [#1 * #1]\n"
      "o<square> endsub\n"
      "#<half> = 100\n"
      "o<square> call [6]\n"
      "G0 X#<_value>\n"
      "G0 X#<half>\n"      // the caller's local is untouched
      "o<square> call [4]\n"
      "M2\n");
  EXPECT_EQ(rapid_x(p), (std::vector<double>{3, 36, 100, 2}));
}

TEST(IsoControlFlow, NumberedSubroutineAndRecursion) {
  // Factorial by recursion: #1 = n, returns n! in #<_value>.
  const auto p = parse_ok(
      "o100 sub\n"
      "o101 if [#1 LE 1]\n o100 return [1]\no101 endif\n"
      "o100 call [#1 - 1]\n"
      "o100 endsub [#1 * #<_value>]\n"
      "o100 call [5]\nG0 X#<_value>\n");
  EXPECT_EQ(rapid_x(p), (std::vector<double>{120}));
}

// A return's O-number need not be its subroutine's: inside a definition any `oN return` returns from
// it, as in LinuxCNC 2.9's retval.ngc (`o1010 return` inside sub o1000's `o1010 if`); outside every
// definition it is an error.
TEST(IsoControlFlow, AReturnUnderAnyONumberReturnsFromItsSubroutine) {
  const auto p = parse_ok(
      "o1000 sub\n"
      "o1010 if [#1 GT 0]\no1010 return [123 * #1]\no1010 endif\n"
      "o1020 if [#1 LT 0]\no1020 return\no1020 endif\n"
      "o1000 endsub [4712]\n"
      "o1000 call [0]\nG0 X#<_value>\n"
      "o1000 call [2]\nG0 X#<_value>\n"
      "o1000 call [-1]\nG0 X#<_value>\n");
  EXPECT_EQ(rapid_x(p), (std::vector<double>{4712, 246, 0}));
  EXPECT_EQ(one_error("o9999 return [7]\nM2\n"), "t.ngc:1:1: error: o9999 return outside a subroutine definition");
}

TEST(IsoControlFlow, SubroutineFromAFileOnTheSearchPath) {
  const auto dir = std::filesystem::temp_directory_path() / "softmc_iso_subs";
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "hole.ngc") << "o<hole> sub\nG0 X#1 Y#2\no<hole> endsub\n";
  iso::ParseOptions opt;
  opt.subroutine_path = {dir.string()};
  const auto r = iso::parse("o<hole> call [3] [4]\no<hole> call [5] [6]\n", "t.ngc", opt);
  ASSERT_TRUE(r.program);
  EXPECT_EQ(rapid_x(*r.program), (std::vector<double>{3, 5}));
  ASSERT_EQ(r.program->files.size(), 2u);
  EXPECT_EQ(r.program->instructions[0].loc.file, 1u);  // the move was made in hole.ngc, line 2
  EXPECT_EQ(r.program->instructions[0].loc.line, 2u);
  EXPECT_EQ(one_error("o<missing> call\n"),
            "t.ngc:1:1: error: subroutine o<missing> is not defined in the program, and no missing.ngc on the subroutine path");
}

TEST(IsoControlFlow, StructureErrorsInOnePass) {
  const auto e = parse_errors("o1 if [1]\nG0 X1\no2 endif\no3 endwhile\no4 while [1]\n");
  EXPECT_EQ(e, (std::vector<std::string>{
                   "t.ngc:1:1: error: o1 if has no o1 endif",
                   "t.ngc:3:1: error: o2 endif does not match the open o1 if (line 1)",
                   "t.ngc:4:1: error: o3 endwhile does not match the open o1 if (line 1)",
                   "t.ngc:5:1: error: o4 while has no o4 endwhile",
               }));
  EXPECT_EQ(one_error("o5 break\n"), "t.ngc:1:1: error: o5 break outside a loop named o5");
  EXPECT_EQ(one_error("G0 X1 o5 if [1]\n"), "t.ngc:1:7: error: O word must be the first word of its line (after an optional N)");
}

TEST(IsoRobustness, EndlessLoopHitsTheIterationLimit) {
  iso::ParseOptions opt;
  opt.max_loop_iterations = 1000;
  const auto e = parse_errors("o1 while [1]\nG0 X1\no1 endwhile\n", opt);
  EXPECT_EQ(e, std::vector<std::string>{"t.ngc:1:1: error: loop o1 ran more than 1000 times: endless loop? (stopping here)"});
  // A do-loop and a huge repeat too.
  EXPECT_EQ(parse_errors("o2 do\no2 while [1]\n", opt).size(), 1u);
  EXPECT_EQ(parse_errors("o3 repeat [1000000000]\no3 endrepeat\n", opt),
            std::vector<std::string>{"t.ngc:1:1: error: repeat count 1e+09 is above the loop limit 1000"});
}

TEST(IsoRobustness, EndlessRecursionHitsTheDepthLimit) {
  EXPECT_EQ(parse_errors("o1 sub\no1 call\no1 endsub\no1 call\n"),
            std::vector<std::string>{"t.ngc:2:1: error: subroutine calls nested more than 32 deep (endless recursion?)"});
}

TEST(IsoRobustness, NestedLoopsAreBoundedInTotal) {
  iso::ParseOptions opt;
  opt.max_blocks = 5000;
  const auto e = parse_errors("o1 repeat [1000]\no2 repeat [1000]\nG0 X1\no2 endrepeat\no1 endrepeat\n", opt);
  ASSERT_EQ(e.size(), 1u);
  // One pass over the 6 lines of text is always allowed; the loops may add max_blocks more.
  EXPECT_NE(e[0].find("the program runs more than 5006 blocks"), std::string::npos);
}

TEST(IsoRobustness, MissingSubroutineFileAndGarbageInIt) {
  const auto dir = std::filesystem::temp_directory_path() / "softmc_iso_subs_bad";
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "junk.ngc", std::ios::binary) << std::string("\x01\x02o<junk> sub\n\xff\xfe\n", 14);
  iso::ParseOptions opt;
  opt.subroutine_path = {dir.string()};
  const auto r = iso::parse("o<junk> call\n", "t.ngc", opt);
  EXPECT_FALSE(r.program);
  EXPECT_FALSE(r.diagnostics.empty());
}

TEST(IsoMessages, MsgDebugAndPrintComments) {
  const auto p = parse_ok("#1 = 2.5\n(MSG, Load the sheet)\n(debug, radius is #1)\nG0 X1 (print,x=#1)\n");
  ASSERT_EQ(p.instructions.size(), 4u);
  EXPECT_EQ(op_at<Message>(p, 0).text, " Load the sheet");
  EXPECT_EQ(op_at<Message>(p, 0).kind, MessageKind::Msg);
  EXPECT_EQ(op_at<Message>(p, 1).text, " radius is 2.500000");
  EXPECT_EQ(op_at<Message>(p, 2).kind, MessageKind::Print);  // comments come before the block's motion
  EXPECT_TRUE(std::holds_alternative<Rapid>(p.instructions[3].op));
}

TEST(IsoMessages, DebugShowsTheValuesAfterTheLinesAssignments) {
  // LinuxCNC runs a block's comments after the line's parameters are set: rs274 -g prints
  // MESSAGE(" value is 5.250000") for "#1=5.25 (DEBUG, value is #1)".
  const auto p = parse_ok("#1=5.25 (DEBUG, value is #1)\n#<_g>=3 (PRINT,g=#<_g>)\n");
  EXPECT_EQ(messages(p), (std::vector<std::string>{" value is 5.250000", "g=3.000000"}));
}

TEST(IsoMessages, DebugSubstitutesAsLinuxCnc) {
  // rs274 -g: a parameter number is the digits right after '#' (spaces end it, a point is text),
  // #[..] and "# 1" stay as written, a parameter that does not exist prints "######".
  const auto p = parse_ok(
      "#1=1.5\n#12=7\n#<ab>=3\n"
      "(DEBUG,a #1 2 b)\n(DEBUG,c #1  d)\n(DEBUG,e #1x)\n(DEBUG,f #[1] g)\n(DEBUG,i #1.5 j)\n(DEBUG,k # 1 l)\n"
      "(DEBUG,m #12)\n(DEBUG,n ##1)\n(DEBUG,o #<nope> p)\n(DEBUG,q #99999 r)\n(DEBUG,s #<A B> t)\n");
  const std::vector<std::string> want = {"a 1.500000 2 b", "c 1.500000  d", "e 1.500000x", "f #[1] g",
                                         "i 1.500000.5 j", "k # 1 l", "m 7.000000", "n #1.500000",
                                         "o ###### p", "q ###### r", "s 3.000000 t"};
  EXPECT_EQ(messages(p), want);
}

TEST(IsoMessages, DebugPrintsValuesUnder0_0001AsZero) {
  // rs274 -g: 0.00009 and -0.0000006 print as " 0.000000", 0.0001 as " 0.000100", -0.0001 as
  // " -0.000100", 1.000001 as " 1.000001".
  const auto p = parse_ok("#1=0.00009\n(DEBUG, #1)\n#1=-0.0000006\n(DEBUG, #1)\n#1=0.0001\n(DEBUG, #1)\n"
                          "#1=-0.0001\n(DEBUG, #1)\n#1=1.000001\n(DEBUG, #1)\n");
  EXPECT_EQ(messages(p),
            (std::vector<std::string>{" 0.000000", " 0.000000", " 0.000100", " -0.000100", " 1.000001"}));
}

TEST(IsoMessages, TheCommaFollowsTheKeyword) {
  // LinuxCNC's convert_comment: spaces may come before MSG/DEBUG/PRINT but not between it and the
  // comma. rs274 -g: "(MSG , s)" is COMMENT("MSG , s"), "(  MSG, t)" MESSAGE(" t").
  const auto p = parse_ok("(MSG , s)\n(  MSG, t)\n(DEBUG , u)\n(\tMSG, tab)\n(PRINT , v)\n(MSG,)\n(MSG)\n");
  EXPECT_EQ(messages(p), (std::vector<std::string>{" t", " tab", ""}));
}

TEST(IsoMessages, Parameter5599SwitchesDebugOutput) {
  // LinuxCNC: #5599 (1 at start) is writable; 0 silences DEBUG (not PRINT, not MSG). rs274 -g:
  // MESSAGE(" a 1.000000"), then " c" printed, MESSAGE(" d"), MESSAGE(" e").
  const auto p = parse_ok("(DEBUG, a #5599)\n#5599=0\n(DEBUG, b)\n(PRINT, c)\n(MSG, d)\n#5599=1\n(DEBUG, e)\n");
  EXPECT_EQ(messages(p), (std::vector<std::string>{" a 1.000000", " c", " d", " e"}));
}

TEST(IsoMessages, OnlyTheLastCommentOfALineIsActive) {
  // A LinuxCNC block keeps one comment, the last ( ) one of the line. rs274 -g: MESSAGE(" second"),
  // COMMENT("plain") and nothing else, MESSAGE(" fourth"), MESSAGE(" sixth") before the move,
  // MESSAGE(" seventh") (a ';' comment does not count).
  const auto p = parse_ok("(MSG, first) (MSG, second)\n(MSG, third) (plain)\n(plain) (MSG, fourth)\n"
                          "G0 X1 (MSG, fifth) Y2 (DEBUG, sixth)\n(MSG, seventh) ; (MSG, eighth)\n");
  EXPECT_EQ(messages(p), (std::vector<std::string>{" second", " fourth", " sixth", " seventh"}));
}

TEST(IsoMessages, AbortStopsTheProgramWithItsText) {
  // LinuxCNC 2.9: "(ABORT, text)" stops the program with the text as its error, parameters
  // substituted as for DEBUG (rs274 -g: " x=3.000000 y=######", and no move after it); one in a
  // branch that is not taken does nothing.
  EXPECT_EQ(one_error("#1=3\nG0 X1\n(abort, x=#1 y=#<_nope>)\nG0 X2\n"),
            "t.ngc:3:1: error: the program aborts here (ABORT): x=3.000000 y=######");
  EXPECT_EQ(one_error("G0 X1 (ABORT, stop)\n"), "t.ngc:1:7: error: the program aborts here (ABORT): stop");
  EXPECT_EQ(rapid_x(parse_ok("#1=3\no1 if [#1 GT 5]\n(ABORT, too big)\no1 endif\nG0 X1\n")), (std::vector<double>{1}));
}

TEST(IsoM66, WaitInputAndNoBranchingOnItsResult) {
  const auto p = parse_ok("M66 P3 L3 Q2.5\n");
  const auto& w = op_at<WaitInput>(p, 1);
  EXPECT_EQ(w.index, 3);
  EXPECT_TRUE(w.digital);
  EXPECT_EQ(w.mode, 3);
  EXPECT_DOUBLE_EQ(w.timeout_s, 2.5);
  EXPECT_EQ(one_error("M66 P1 L1 Q1\no1 if [#5399 LT 0]\no1 endif\n"),
            "t.ngc:2:8: error: branching on M66 results is not supported: #5399 is only known when the program runs");
  EXPECT_EQ(one_error("M66 P1 L1\n"), "t.ngc:1:1: error: M66 with a wait mode (L1 … L4) needs a Q word: the timeout in seconds");
}
