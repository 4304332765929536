// ISO parser robustness: seeded random and mutated inputs never crash and always answer alike.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <random>
#include <sstream>
#include <string>

#include "iso_test_util.hpp"

using namespace softmc;
using namespace softmc::program;

namespace {

std::string read_example(const char* name) {
  std::ifstream in(std::string(SOFTMC_SOURCE_DIR) + "/examples/thesis/" + name, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::string fingerprint(const iso::ParseResult& r) {
  std::string s;
  for (const auto& d : r.diagnostics) s += d.format() + '\n';
  if (r.program) s += dump(*r.program);
  return s;
}

bool finite(const core::Vec& v) {
  for (double x : v.v)
    if (!std::isfinite(x)) return false;
  return true;
}

// Parses twice (same answer) and checks what holds for any input whatsoever.
void check_any_input(const std::string& text) {
  const auto r = iso::parse(text, "f.ngc");
  ASSERT_EQ(fingerprint(r), fingerprint(iso::parse(text, "f.ngc")));
  ASSERT_EQ(r.program.has_value(), !core::has_errors(r.diagnostics));
  const auto lines = static_cast<std::uint32_t>(std::count(text.begin(), text.end(), '\n') + 1);
  std::uint32_t last_line = 0;
  for (const auto& d : r.diagnostics) {
    ASSERT_GE(d.line, last_line) << "diagnostics out of source order";
    ASSERT_GE(d.line, 1u);
    ASSERT_LE(d.line, lines);
    ASSERT_GE(d.col, 1u);
    ASSERT_FALSE(d.message.empty());
    last_line = d.line;
  }
  if (!r.program) return;
  for (const auto& ins : r.program->instructions) {
    ASSERT_GE(ins.loc.line, 1u);
    ASSERT_LE(ins.loc.line, lines);
    if (const auto* x = std::get_if<Rapid>(&ins.op)) {
      ASSERT_TRUE(finite(x->end));
    }
    if (const auto* x = std::get_if<Linear>(&ins.op)) {
      ASSERT_TRUE(finite(x->end));
      ASSERT_GT(x->feed_mm_s, 0);
    }
    if (const auto* x = std::get_if<Arc>(&ins.op)) {
      ASSERT_TRUE(finite(x->end));
      ASSERT_TRUE(std::isfinite(x->center0) && std::isfinite(x->center1));
      ASSERT_GT(x->feed_mm_s, 0);
      ASSERT_NE(x->turns, 0);
    }
    if (const auto* x = std::get_if<Dwell>(&ins.op)) {
      ASSERT_GE(x->seconds, 0);
    }
  }
}

// Characters that make G-code, so that random text often gets past the lexer.
const std::string kAlphabet = "GXYZIJFPMN0123456789.-+ ()%;/\n\r\tgxyzEUVWAKRS#[";
const std::vector<std::string> kTokens = {"G0", "G1", "G2", "G3", "G4", "G20", "G21", "G90", "G91", "G91.1", "G90.1",
                                          "M3", "M5", "M30", "M2", "F60", "F0", "P2", "X1e999", "X-0", "I10", "J-10",
                                          "(", ")", ";", "%\n", "\n/", std::string(1, '\0'), "Y1.2.3", "X99999999999"};

}  // namespace

TEST(IsoRobustness, RandomBytesNeverCrashAndAreDeterministic) {
  std::mt19937_64 rng(0x5eed'0001);
  for (int n = 0; n < 4000; ++n) {
    const std::size_t len = rng() % 300;
    std::string s;
    for (std::size_t i = 0; i < len; ++i)
      s += (rng() % 2) ? kAlphabet[rng() % kAlphabet.size()] : static_cast<char>(rng() % 256);
    ASSERT_NO_FATAL_FAILURE(check_any_input(s)) << "case " << n;
  }
}

TEST(IsoRobustness, MutatedValidProgramsNeverCrashAndAreDeterministic) {
  std::mt19937_64 rng(0x5eed'0002);
  const std::vector<std::string> bases = {read_example("shield.ngc"), read_example("square.ngc"),
                                          read_example("rounded_rectangle.ngc")};
  int accepted = 0;
  for (int n = 0; n < 3000; ++n) {
    std::string s = bases[n % bases.size()];
    const int edits = 1 + static_cast<int>(rng() % 5);
    for (int e = 0; e < edits && !s.empty(); ++e) {
      const std::size_t at = rng() % s.size();
      switch (rng() % 5) {
        case 0: s[at] = static_cast<char>(rng() % 256); break;
        case 1: s[at] = kAlphabet[rng() % kAlphabet.size()]; break;
        case 2: s.erase(at, 1 + rng() % 8); break;
        case 3: s.insert(at, kTokens[rng() % kTokens.size()]); break;
        case 4: s.insert(at, s.substr(rng() % s.size(), 1 + rng() % 20)); break;
      }
    }
    ASSERT_NO_FATAL_FAILURE(check_any_input(s)) << "case " << n;
    if (iso::parse(s, "f.ngc").program) ++accepted;
  }
  // The mutations must exercise both sides: some programs survive, most are refused.
  EXPECT_GT(accepted, 50);
  EXPECT_LT(accepted, 2950);
}

TEST(IsoRobustness, HugeLinesAndPrograms) {
  check_any_input(std::string(1 << 20, '('));
  check_any_input("G0 X" + std::string(1 << 20, '7'));
  check_any_input(std::string(1 << 20, ' ') + "G0 X1");
  std::string many_words;
  for (int i = 0; i < 100000; ++i) many_words += "G0 ";
  check_any_input(many_words);
  std::string long_program;
  for (int i = 0; i < 100000; ++i) long_program += (i % 2) ? "G0 X1\n" : "G1 X2 F100\n";
  const auto r = iso::parse(long_program, "f.ngc");
  ASSERT_TRUE(r.program);
  EXPECT_EQ(r.program->instructions.size(), 100000u);
  EXPECT_EQ(r.program->instructions.back().loc.line, 100000u);
}

TEST(IsoRobustness, RandomAbsoluteAndIncrementalMovesEndWhereExpected) {
  std::mt19937_64 rng(0x5eed'0003);
  for (int n = 0; n < 300; ++n) {
    iso::ParseOptions opt;
    for (std::size_t a = 0; a < 3; ++a) opt.start[a] = static_cast<double>(rng() % 100);
    core::Vec expect = opt.start;
    bool incremental = false;
    std::string text = "F600\n";
    std::vector<core::Vec> ends;
    for (int k = 0; k < 30; ++k) {
      if (rng() % 4 == 0) {
        incremental = !incremental;
        text += incremental ? "G91 " : "G90 ";
      }
      text += (rng() % 2) ? "G0" : "G1";
      for (std::size_t a = 0; a < 3; ++a) {
        if (rng() % 2) continue;
        const long long thousandths = static_cast<long long>(rng() % 200001) - 100000;
        const std::string num = std::to_string(thousandths / 1000) + "." +
                                std::to_string(std::llabs(thousandths % 1000) + 1000).substr(1);
        const std::string signed_num = (thousandths < 0 && thousandths > -1000) ? "-" + num : num;
        text += std::string(" ") + core::letter(a) + signed_num;
        const double v = std::stod(signed_num);
        expect[a] = incremental ? expect[a] + v : v;
      }
      text += "\n";
      ends.push_back(expect);
    }
    const auto p = iso::parse(text, "f.ngc", opt);
    ASSERT_TRUE(p.program) << text;
    // Blocks without axis words make no instruction; compare only the moves made.
    std::size_t m = 0;
    std::istringstream lines(text);
    std::string line;
    std::getline(lines, line);  // F600
    for (std::size_t k = 0; k < ends.size(); ++k) {
      std::getline(lines, line);
      const bool has_axis = line.find_first_of("XYZ") != std::string::npos;
      if (!has_axis) continue;
      ASSERT_LT(m, p.program->instructions.size());
      const auto& op = p.program->instructions[m++].op;
      const core::Vec end = std::holds_alternative<Rapid>(op) ? std::get<Rapid>(op).end : std::get<Linear>(op).end;
      for (std::size_t a = 0; a < 3; ++a) ASSERT_NEAR(end[a], ends[k][a], 1e-9) << text;
    }
    EXPECT_EQ(m, p.program->instructions.size());
  }
}
