// The one-pass path for plain straight moves and arcs (fast_block.hpp) and the plain-number reader
// give exactly what the general lexer → block check → interpreter path gives.
#include <gtest/gtest.h>

#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "iso_test_util.hpp"
#include "program/iso/expression.hpp"

using namespace softmc;
using namespace softmc::program;

namespace {

namespace fs = std::filesystem;

std::string fingerprint(const iso::ParseResult& r) {
  std::string s;
  for (const auto& d : r.diagnostics) s += d.format() + '\n';
  if (r.program) s += dump(*r.program);
  return s;
}

// Both paths on the same text: same diagnostics, same instructions (the dump prints 6 decimals,
// so the end points are compared bit for bit as well).
void expect_same(const std::string& text, const std::string& what) {
  iso::ParseOptions fast, slow;
  slow.fast_path = false;
  const auto a = iso::parse(text, "f.ngc", fast);
  const auto b = iso::parse(text, "f.ngc", slow);
  ASSERT_EQ(fingerprint(a), fingerprint(b)) << what;
  if (!a.program) return;
  ASSERT_EQ(a.program->instructions.size(), b.program->instructions.size()) << what;
  for (std::size_t i = 0; i < a.program->instructions.size(); ++i) {
    const auto& x = a.program->instructions[i];
    const auto& y = b.program->instructions[i];
    ASSERT_EQ(x.loc.line, y.loc.line) << what;
    ASSERT_EQ(x.loc.col, y.loc.col) << what;
    ASSERT_EQ(x.op.index(), y.op.index()) << what;
    if (const auto* l = std::get_if<Linear>(&x.op)) {
      ASSERT_EQ(std::memcmp(&l->end, &std::get<Linear>(y.op).end, sizeof l->end), 0) << what << " line " << x.loc.line;
      ASSERT_EQ(l->feed_mm_s, std::get<Linear>(y.op).feed_mm_s) << what;
    }
    if (const auto* r = std::get_if<Rapid>(&x.op)) {
      ASSERT_EQ(std::memcmp(&r->end, &std::get<Rapid>(y.op).end, sizeof r->end), 0) << what << " line " << x.loc.line;
    }
    if (const auto* c = std::get_if<Arc>(&x.op)) {
      const auto& d = std::get<Arc>(y.op);
      ASSERT_EQ(std::memcmp(&c->end, &d.end, sizeof c->end), 0) << what << " line " << x.loc.line;
      ASSERT_EQ(c->center0, d.center0) << what;
      ASSERT_EQ(c->center1, d.center1) << what;
      ASSERT_EQ(c->turns, d.turns) << what;
      ASSERT_EQ(c->feed_mm_s, d.feed_mm_s) << what;
    }
  }
}

std::string read(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Random lines of the kinds the fast path takes and the ones next to them that it must leave alone
// (modes, offsets, compensation, NURBS, errors), so that every hand-over between the paths is met.
std::string random_program(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-50, 50);
  auto num = [&](int decimals) { return fmt::format("{:.{}f}", u(rng), decimals); };
  static const char* const kModes[] = {"G90", "G91", "G20", "G21", "G90.1", "G91.1", "G17", "G18", "G94", "G93",
                                       "G54", "G55", "G92 X0 Y0", "G92.1", "G10 L2 P1 X3", "G41.1 D0.5",
                                       "G40", "G80", "M3", "M5", "F120", "F0", "G43.1 Z1", "G49", "G64 P0.01"};
  std::string s;
  const int n = 20 + static_cast<int>(rng() % 60);
  for (int i = 0; i < n; ++i) {
    switch (rng() % 12) {
      case 0: s += kModes[rng() % std::size(kModes)]; break;
      case 1: s += fmt::format("G0 X{} Y{}", num(3), num(3)); break;
      case 2: s += fmt::format("G1 X{} Y{} F{}", num(4), num(4), 100 + rng() % 2000); break;
      case 3: s += fmt::format("X{} Y{}", num(4), num(4)); break;
      case 4: s += fmt::format("N{} G1 Z{}", i, num(2)); break;
      case 5: s += fmt::format("G{} X{} Y{} I{} J{}", rng() % 2 ? 2 : 3, num(3), num(3), num(3), num(3)); break;
      case 6: s += fmt::format("g1x{}y{}", num(1), num(1)); break;                     // lower case, no spaces
      case 7: s += fmt::format("G1 X{} Y {}", num(2), num(2)); break;                   // a space inside
      case 8: s += rng() % 2 ? "G1" : "G0"; break;                                      // no axis words
      case 9: s += fmt::format("X{} Y{} (comment) ; more", num(4), num(4)); break;
      case 10: s += fmt::format("G5.2 X{} Y{}\nX{} Y{}\nX{} Y{}\nG5.3", num(1), num(1), num(1), num(1), num(1), num(1)); break;
      default: s += fmt::format("G1 X{} Q1", num(2)); break;                            // an error
    }
    s += rng() % 10 == 0 ? "\r\n" : "\n";
  }
  return s + "M30\n";
}

}  // namespace

TEST(IsoFastPath, SameResultAsTheGeneralPathOnEveryExample) {
  std::size_t files = 0;
  for (const char* dir : {"tests/golden/iso", "examples/gcode", "examples/thesis", "tests/fuzz/corpus/iso"}) {
    const fs::path d = fs::path(SOFTMC_SOURCE_DIR) / dir;
    if (!fs::is_directory(d)) continue;
    for (const auto& e : fs::directory_iterator(d)) {
      if (e.path().extension() != ".ngc") continue;
      expect_same(read(e.path()), e.path().string());
      ++files;
    }
  }
  EXPECT_GT(files, 20u);
}

TEST(IsoFastPath, SameResultAsTheGeneralPathOnRandomPrograms) {
  std::mt19937_64 rng(42);
  for (int k = 0; k < 2000; ++k) {
    const std::string text = random_program(rng);
    expect_same(text, text);
    if (HasFatalFailure()) return;
  }
}

// read_plain_number gives from_chars' correctly rounded value whenever it takes a number, and
// refuses what it cannot read exactly (the general reader then reads it).
TEST(IsoFastPath, PlainNumbersReadExactlyAsFromChars) {
  std::mt19937_64 rng(3);
  int taken = 0;
  for (int k = 0; k < 200000; ++k) {
    std::string s;
    if (rng() % 4 == 0) s += rng() % 2 ? '-' : '+';
    const int int_digits = static_cast<int>(rng() % 12), frac_digits = static_cast<int>(rng() % 14);
    for (int i = 0; i < int_digits; ++i) s += static_cast<char>('0' + rng() % 10);
    const bool point = rng() % 5 != 0;
    if (point) s += '.';
    for (int i = 0; point && i < frac_digits; ++i) s += static_cast<char>('0' + rng() % 10);
    const std::string line = s + (rng() % 2 ? " Y1" : "");
    std::size_t i = 0;
    double v = 0;
    if (!iso::read_plain_number(line, i, v)) continue;
    ++taken;
    const std::size_t start = (s[0] == '-' || s[0] == '+') ? 1 : 0;
    double want = 0;
    const auto r = std::from_chars(s.data() + start, s.data() + s.size(), want, std::chars_format::fixed);
    ASSERT_EQ(r.ec, std::errc()) << s;
    if (s[0] == '-' && want != 0) want = -want;
    ASSERT_EQ(std::memcmp(&v, &want, sizeof v), 0) << s << " read " << v << " want " << want;
    ASSERT_TRUE(i == s.size() + 1 || i == s.size()) << s;  // past the number and the space after it
  }
  EXPECT_GT(taken, 100000);
  // What it leaves to the general reader.
  for (const char* s : {"1 0.5", "1e3", "1.2.3", "-", ".", " 5", "12345678901234567"}) {
    std::size_t i = 0;
    double v = 0;
    EXPECT_FALSE(iso::read_plain_number(s, i, v)) << s;
    EXPECT_EQ(i, 0u);
  }
}
