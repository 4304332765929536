// Cost of one interpolation cycle (4 axes), and of a whole simulated machine cycle.
#include <benchmark/benchmark.h>

#include "motion/interp/interpolator.hpp"
#include "motion/planner/planner.hpp"

using namespace softmc;

namespace {
motion::MachineLimits four_axes() {
  motion::MachineLimits m;
  for (int i = 0; i < 4; ++i) m.axis[i] = {200, 2000, 0, -1e6, 1e6};
  m.axis[6] = m.axis[3];  // X Y Z U
  m.axis[3] = {};
  return m;
}

// Alternating 4-axis lines and XY arcs with a U move (helix-like), each many cycles long.
void refill(motion::Planner& p, core::Vec& at, int& k) {
  while (!p.queue().full()) {
    core::Vec to = at;
    to[0] += 10;
    to[1] += (k % 2 ? 5 : -5);
    to[2] += 1;
    to[6] += 2;
    motion::Segment g = (k % 2) ? motion::make_line(at, to)
                                : motion::make_arc(at, to, 0, 1, at[0] + 5, at[1] + (to[1] - at[1]) / 2 + 3, 1);
    if (p.push({g, 100, false, static_cast<std::uint32_t>(k)}) != motion::PlanResult::Ok) std::abort();
    at = to;
    ++k;
  }
}
}  // namespace

static void BM_InterpolationCycle4Axes(benchmark::State& state) {
  motion::Planner planner(four_axes(), 4096);
  core::Vec at{};
  int k = 0;
  refill(planner, at, k);
  motion::Interpolator in(planner.queue(), core::Vec{});
  for (auto _ : state) {
    const auto& sp = in.step(0.001);
    benchmark::DoNotOptimize(sp.pos);
    if (planner.queue().size() < 16) {
      state.PauseTiming();
      refill(planner, at, k);
      state.ResumeTiming();
    }
  }
}
BENCHMARK(BM_InterpolationCycle4Axes);

BENCHMARK_MAIN();
