// ISO lexer: words with their columns, comments, spaces inside numbers, and every lexical error.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "program/iso/lexer.hpp"

using namespace softmc::program::iso;

namespace {

LexedLine lex_ok(std::string_view s) {
  auto l = lex_line(s);
  EXPECT_FALSE(l.error) << s << ": " << (l.error ? l.error->message : "");
  return l;
}

// The error a line gives, as "col: message".
std::string lex_error(std::string_view s) {
  auto l = lex_line(s);
  EXPECT_TRUE(l.error) << s;
  return l.error ? std::to_string(l.error->col) + ": " + l.error->message : "";
}

}  // namespace

TEST(IsoLexer, WordsCarryLetterValueAndColumn) {
  const auto l = lex_ok("G1 X10.5 y-2");
  ASSERT_EQ(l.kind, LineKind::Block);
  ASSERT_EQ(l.words.size(), 3u);
  EXPECT_EQ(l.words[0].letter, 'G');
  EXPECT_EQ(l.words[0].value, 1.0);
  EXPECT_EQ(l.words[0].col, 1u);
  EXPECT_EQ(l.words[1].letter, 'X');
  EXPECT_EQ(l.words[1].value, 10.5);
  EXPECT_EQ(l.words[1].col, 4u);
  EXPECT_EQ(l.words[2].letter, 'Y');  // lower case letters are the same words
  EXPECT_EQ(l.words[2].value, -2.0);
  EXPECT_EQ(l.words[2].col, 10u);
}

TEST(IsoLexer, WordsNeedNoSpacesBetweenThem) {
  const auto l = lex_ok("g01x2.y+.5");
  ASSERT_EQ(l.words.size(), 3u);
  EXPECT_EQ(l.words[0].value, 1.0);
  EXPECT_EQ(l.words[1].value, 2.0);
  EXPECT_EQ(l.words[2].value, 0.5);
  EXPECT_EQ(l.words[2].col, 7u);
}

TEST(IsoLexer, SpacesInsideANumberAreIgnoredAsRs274Says) {
  const auto l = lex_ok("X 1 0.5 Y - 5");
  ASSERT_EQ(l.words.size(), 2u);
  EXPECT_EQ(l.words[0].value, 10.5);
  EXPECT_EQ(l.words[1].value, -5.0);
  EXPECT_EQ(l.words[1].col, 9u);
}

TEST(IsoLexer, CommentsAreSkippedAndColumnsStayRight) {
  const auto l = lex_ok("G1 (to the corner) X1 ; the rest (is) ignored X99");
  ASSERT_EQ(l.words.size(), 2u);
  EXPECT_EQ(l.words[1].letter, 'X');
  EXPECT_EQ(l.words[1].col, 20u);
  EXPECT_EQ(lex_ok("(only a comment)").kind, LineKind::Empty);
  EXPECT_EQ(lex_ok("   ; nothing").kind, LineKind::Empty);
  EXPECT_EQ(lex_ok("").kind, LineKind::Empty);
  EXPECT_EQ(lex_ok(" \t\r").kind, LineKind::Empty);
}

TEST(IsoLexer, PercentAndBlockDeleteLines) {
  EXPECT_EQ(lex_ok("%").kind, LineKind::Percent);
  EXPECT_EQ(lex_ok("  % tape end").kind, LineKind::Percent);
  EXPECT_EQ(lex_ok("/G1 X1").kind, LineKind::BlockDelete);
  EXPECT_EQ(lex_ok(" / anything #$").kind, LineKind::BlockDelete);
}

TEST(IsoLexer, MinusZeroReadsAsPlainZero) {
  const auto l = lex_ok("X-0");
  ASSERT_EQ(l.words.size(), 1u);
  EXPECT_FALSE(std::signbit(l.words[0].value));  // dumps must not print "-0.000000"
}

TEST(IsoLexer, CarriageReturnIsWhiteSpace) {
  const auto l = lex_ok("G0 X1\r");
  ASSERT_EQ(l.words.size(), 2u);
}

TEST(IsoLexer, WordWithoutNumber) {
  EXPECT_EQ(lex_error("G1 X Y2"), "4: X word has no number");
  EXPECT_EQ(lex_error("G1 X"), "4: X word has no number");
  EXPECT_EQ(lex_error("X-"), "1: malformed number: no digits");
  EXPECT_EQ(lex_error("X."), "1: malformed number: no digits");
}

TEST(IsoLexer, MalformedNumberPointsAtTheWordLetter) {
  EXPECT_EQ(lex_error("G1 X1.2.3"), "4: malformed number: two decimal points");
  EXPECT_EQ(lex_error("G1 X1e3"), "4: malformed number: RS274 has no exponent notation (write the number out in full)");
}

TEST(IsoLexer, HugeNumbersAreOutOfRange) {
  EXPECT_EQ(lex_error("G1 X1e999"), "4: number out of range");
  EXPECT_EQ(lex_error("Y" + std::string(400, '9')), "1: number out of range");
  EXPECT_EQ(lex_error("F2000000000"), "1: number out of range (magnitude above 1e+09)");
  EXPECT_FALSE(lex_line("X1000000000").error);  // the bound itself is fine
}

TEST(IsoLexer, VeryLongNumbersWithinRangeRead) {
  const auto l = lex_ok("X" + std::string(5000, '0') + "1." + std::string(5000, '0') + "1");
  ASSERT_EQ(l.words.size(), 1u);
  EXPECT_NEAR(l.words[0].value, 1.0, 1e-12);
}

TEST(IsoLexer, CommentErrors) {
  EXPECT_EQ(lex_error("G1 (a (b) c) X1"), "7: nested comment: '(' inside a comment");
  EXPECT_EQ(lex_error("G1 X1 (open"), "7: comment has no closing ')'");
  EXPECT_EQ(lex_error("G1 X1 )"), "7: ')' without an opening '('");
}

TEST(IsoLexer, StrayCharacters) {
  EXPECT_EQ(lex_error("10 X1"), "1: number without a word letter in front of it");
  EXPECT_EQ(lex_error("G1 #1"), "4: parameter without '=': a parameter is set with #n = value");
  EXPECT_EQ(lex_error("G1 [1]"), "4: expression without a word letter in front of it");
  EXPECT_EQ(lex_error("G1 X1]"), "6: ']' without an opening '['");
  EXPECT_EQ(lex_error("G1 X1 %"), "7: '%' must be alone on its line");
  EXPECT_EQ(lex_error("G1 /X1"), "4: '/' (block delete) must be the first character of the line");
  EXPECT_EQ(lex_error("G1 X1 &"), "7: unexpected character '&'");
  EXPECT_EQ(lex_error(std::string("G1 \x01", 4)), "4: unexpected byte 0x01");
  EXPECT_EQ(lex_error(std::string("G1\0", 3)), "3: unexpected byte 0x00");
  EXPECT_EQ(lex_error("G1 \xC3\xA9"), "4: unexpected byte 0xC3");
}

TEST(IsoLexer, AnyLetterMakesAWordTheBlockCheckDecides) {
  const auto l = lex_ok("E1 Q2 S3");
  ASSERT_EQ(l.words.size(), 3u);
  EXPECT_EQ(l.words[0].letter, 'E');
}
