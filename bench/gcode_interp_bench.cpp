// Interpreter throughput (MB/s, lines/s) on a generated CAM-like program, and the `softmc moves`
// writer on top of it. The comparison with LinuxCNC's rs274 is bench/gcode_compare.sh.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>
#include <string>

#include <fmt/format.h>

#include "moves.hpp"
#include "program/iso/parser.hpp"

namespace {

using namespace softmc;

// The same kind of text as bench/gcode_gen.py: short chords with 4 decimals, arcs with I/J, plunges.
std::string cam_program(std::size_t n_lines) {
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(0, 1);
  std::string s = "G21 G90 G17 G91.1\nG0 Z5\nM3\n";
  std::size_t lines = 3;
  while (lines < n_lines) {
    const double cx = 20 + 380 * u(rng), cy = 20 + 280 * u(rng), r = 5 + 25 * u(rng);
    double a = 0, x = cx + r, y = cy;
    s += fmt::format("G0 X{:.3f} Y{:.3f}\nG1 Z-1.5 F300\n", x, y);
    lines += 2;
    for (int k = 0; k < 200 && lines < n_lines; ++k, ++lines) {
      const double p = u(rng);
      if (p < 0.85) {
        a += 0.01 + 0.07 * u(rng);
        x = cx + r * std::cos(a);
        y = cy + r * std::sin(a);
        s += fmt::format("X{:.4f} Y{:.4f}\n", x, y);
      } else if (p < 0.95) {
        const double a2 = a + 0.1 + 0.5 * u(rng);
        const double ex = cx + r * std::cos(a2), ey = cy + r * std::sin(a2);
        s += fmt::format("G3 X{:.4f} Y{:.4f} I{:.4f} J{:.4f}\nG1\n", ex, ey, cx - x, cy - y);
        ++lines;
        x = ex;
        y = ey;
        a = a2;
      } else {
        s += fmt::format("N{} G1 Z{:.3f} F1200\n", lines, -1.5 - u(rng));
      }
    }
    s += "G0 Z5\n";
    ++lines;
  }
  s += "M5\nM30\n";
  return s;
}

std::size_t count_lines(const std::string& s) {
  std::size_t n = 0;
  for (char c : s) n += c == '\n';
  return n;
}

void report(benchmark::State& state, const std::string& text) {
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * text.size()));
  state.counters["lines/s"] = benchmark::Counter(static_cast<double>(count_lines(text) * state.iterations()),
                                                 benchmark::Counter::kIsRate);
}

void BM_GcodeInterpret(benchmark::State& state) {
  const std::string text = cam_program(static_cast<std::size_t>(state.range(0)));
  for (auto _ : state) {
    auto r = program::iso::parse(text, "cam.ngc");
    if (!r.program) state.SkipWithError("the generated program did not parse");
    benchmark::DoNotOptimize(r);
  }
  report(state, text);
}
BENCHMARK(BM_GcodeInterpret)->Arg(100000)->Unit(benchmark::kMillisecond);

// Interpretation plus the JSON Lines writer into /dev/null: what `softmc moves` does.
void BM_GcodeMovesToDevNull(benchmark::State& state) {
  const std::string text = cam_program(static_cast<std::size_t>(state.range(0)));
  std::FILE* null = std::fopen("/dev/null", "w");
  for (auto _ : state) {
    auto r = program::iso::parse(text, "cam.ngc");
    if (!r.program) state.SkipWithError("the generated program did not parse");
    else app::write_moves(null, *r.program, 0b111);
  }
  std::fclose(null);
  report(state, text);
}
BENCHMARK(BM_GcodeMovesToDevNull)->Arg(100000)->Unit(benchmark::kMillisecond);

// What `softmc moves FILE > /dev/null` does: the file read in one go, instructions streamed into
// the writer in batches (no whole-program IR).
void BM_GcodeMovesStreamed(benchmark::State& state) {
  const std::string text = cam_program(static_cast<std::size_t>(state.range(0)));
  const std::string path = (std::filesystem::temp_directory_path() / "softmc_bench_cam.ngc").string();
  if (std::FILE* f = std::fopen(path.c_str(), "wb")) {
    std::fwrite(text.data(), 1, text.size(), f);
    std::fclose(f);
  }
  std::FILE* null = std::fopen("/dev/null", "w");
  for (auto _ : state) {
    const auto d = app::write_program_moves(null, path, {}, 0b111);
    if (core::has_errors(d)) state.SkipWithError("the generated program did not parse");
  }
  std::fclose(null);
  std::remove(path.c_str());
  report(state, text);
}
BENCHMARK(BM_GcodeMovesStreamed)->Arg(1000000)->Unit(benchmark::kMillisecond);

}  // namespace
