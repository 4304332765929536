// `softmc moves` writer (apps/softmc/moves.cpp): numbers as fmt's shortest round trip, streaming
// equal to the whole-program writer, and nothing written for a program with errors.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <random>
#include <string>

#include <fmt/format.h>

#include "golden_setup.hpp"
#include "moves.hpp"
#include "program/iso/parser.hpp"

namespace fs = std::filesystem;
using namespace softmc;

namespace {

std::string file_text(std::FILE* f) {
  std::fflush(f);
  std::rewind(f);
  std::string s;
  char buf[4096];
  for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, f)) > 0;) s.append(buf, n);
  return s;
}

}  // namespace

// Every number is the shortest decimal that reads back as the same double, laid out as fmt's
// "{}" (the writer's own fast path for short decimals and its memo must not change a digit).
TEST(MovesWriter, NumbersAreTheShortestRoundTripAsFmtPrintsThem) {
  std::mt19937_64 rng(5);
  program::Program p;
  p.files = {"t.ngc"};
  std::vector<double> values;
  for (int k = 0; k < 20000; ++k) {
    double v = 0;
    switch (k % 5) {
      case 0: v = static_cast<double>(static_cast<std::int64_t>(rng() % 20000000) - 10000000) / 10000.0; break;
      case 1: v = std::ldexp(static_cast<double>(rng() % (1ull << 53)), -static_cast<int>(rng() % 70)); break;
      case 2: v = static_cast<double>(rng() % 100000) * std::pow(10.0, static_cast<int>(rng() % 30) - 15); break;
      case 3: v = (static_cast<double>(rng() % 2000000) - 1e6) / 1e4 * 25.4; break;
      default: {
        const std::uint64_t bits = rng();
        std::memcpy(&v, &bits, sizeof v);
        if (!std::isfinite(v)) v = 1e-300;
      }
    }
    if (k % 7 == 0 && !values.empty()) v = values.back();  // repeated values go through the memo
    values.push_back(v);
    core::Vec e;
    e[0] = v;
    p.instructions.push_back(program::Instruction{{0, 1, 1}, program::Linear{e, 1}});
  }
  const std::string out = app::moves_jsonl(p, 0b1);
  std::size_t pos = 0;
  for (double v : values) {
    const std::size_t at = out.find("\"X\":", pos);
    ASSERT_NE(at, std::string::npos);
    const std::size_t end = out.find('}', at);
    const std::string got = out.substr(at + 4, end - at - 4);
    ASSERT_EQ(got, fmt::format("{}", v == 0 ? 0.0 : v)) << v;
    pos = end;
  }
}

// The streamed `softmc moves` output equals the writer over the whole program, for every golden
// program, into a file as into a pipe-like (held) output.
TEST(MovesWriter, StreamedOutputEqualsTheWholeProgram) {
  const fs::path dir = fs::path(SOFTMC_SOURCE_DIR) / "tests" / "golden" / "iso";
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.path().extension() != ".ngc") continue;
    const auto r = program::iso::parse_file(e.path().string(), golden::setup().options());
    ASSERT_TRUE(r.program) << e.path();
    std::FILE* f = std::tmpfile();
    ASSERT_NE(f, nullptr);
    program::iso::ParseOptions opt = golden::setup().options();
    opt.sink_batch = 7;  // many small batches
    const auto d = app::write_program_moves(f, e.path().string(), opt, 0b111);
    EXPECT_FALSE(core::has_errors(d));
    EXPECT_EQ(file_text(f), app::moves_jsonl(*r.program, 0b111)) << e.path();
    std::fclose(f);
  }
}

// A program with an error writes nothing; what the file held before stays.
TEST(MovesWriter, NothingIsWrittenForAProgramWithAnError) {
  const fs::path prog = fs::temp_directory_path() / "softmc_moves_writer_bad.ngc";
  {
    std::FILE* p = std::fopen(prog.c_str(), "w");
    ASSERT_NE(p, nullptr);
    std::fputs("G21 G90 F600\n", p);
    for (int i = 0; i < 30000; ++i) std::fprintf(p, "G1 X%d Y1\n", i % 50);  // > 1 MiB of output first
    std::fputs("G1 X1 Q5\nM30\n", p);
    std::fclose(p);
  }
  std::FILE* f = std::tmpfile();
  ASSERT_NE(f, nullptr);
  std::fputs("kept\n", f);
  const auto d = app::write_program_moves(f, prog.string(), {}, 0b111);
  EXPECT_TRUE(core::has_errors(d));
  EXPECT_EQ(file_text(f), "kept\n");
  std::fclose(f);
  fs::remove(prog);
}
