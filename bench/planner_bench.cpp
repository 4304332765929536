// Look-ahead planner throughput (segments planned per CPU second) and the cost of one cycle.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <ctime>
#include <cmath>
#include <cstdint>
#include <vector>

#include "control/channel.hpp"
#include "motion/geometry/polyline_smoothing.hpp"
#include "motion/interp/interpolator.hpp"
#include "motion/planner/planner.hpp"

using namespace softmc;

namespace {
motion::MachineLimits xyz() {
  motion::MachineLimits m;
  for (int i = 0; i < 3; ++i) m.axis[i] = {200, 2000, 0, -1e6, 1e6};
  m.axis[6] = m.axis[0];  // U: a 4th axis
  return m;
}

// One push per iteration, round the requests again and again: the window is emptied as it fills
// (the pushes, not the queue, are timed) and cleared at the start of each round. Returns the pushes.
std::size_t push_rounds(benchmark::State& state, motion::Planner& planner, const std::vector<motion::PathRequest>& reqs) {
  std::size_t k = 0;
  for (auto _ : state) {
    while (planner.queue().full()) planner.queue().ring().pop();
    if (k % reqs.size() == 0) planner.queue().clear();  // start again from the first point
    benchmark::DoNotOptimize(planner.push(reqs[k++ % reqs.size()]));
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
  return k;
}

// CAM-like closed polyline: 0.05 mm chords of a 50 mm circle in XY with Z and U swinging along
// (4 axes), so it can be run round and round.
std::vector<motion::PathRequest> polyline(double chord_mm) {
  std::vector<motion::PathRequest> v;
  const int n = static_cast<int>(2 * 3.141592653589793 * 50 / chord_mm);
  auto pt = [n](int k) {
    const double a = 2 * 3.141592653589793 * (k % n) / n;
    core::Vec p{};
    p[0] = 50 * std::sin(a);
    p[1] = 50 - 50 * std::cos(a);
    p[2] = 2 - 2 * std::cos(a);
    p[6] = 3 * std::sin(a);
    return p;
  };
  core::Vec at = pt(0);
  for (int k = 1; k <= n; ++k) {
    const core::Vec to = pt(k);
    v.push_back({motion::make_line(at, to), 100, false, static_cast<std::uint32_t>(k)});
    at = to;
  }
  return v;
}
}  // namespace

// Planning only: push (validation, blend, junction, incremental backward pass); the consumer pops.
static void BM_PlanLines(benchmark::State& state) {
  const auto reqs = polyline(0.05);
  motion::Planner planner(xyz(), static_cast<std::size_t>(state.range(0)));
  std::size_t k = 0;
  for (auto _ : state) {
    while (planner.queue().full()) planner.queue().ring().pop();  // the interpolator's share, O(1)
    benchmark::DoNotOptimize(planner.push(reqs[k++ % reqs.size()]));
    if (k % 16 == 0) planner.queue().settle();  // the backward pass, once per cycle of 16 pushes
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
  state.counters["segments_per_s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_PlanLines)->Arg(256)->Arg(10'000);

// Planning a zig-zag of 5 mm lines turning 60° at every corner on a jerk-limited machine: each
// corner gets a quintic blend (Planner "Corner blends": its arc-length table and sampled limits are
// built in push) where the arc would get a curvature step.
static void BM_PlanCornersJerk(benchmark::State& state) {
  auto lim = xyz();
  for (int i : {0, 1, 2}) lim.axis[static_cast<std::size_t>(i)].j_max_mm_s3 = 10'000;
  std::vector<motion::PathRequest> reqs;
  core::Vec at{};
  for (int k = 0; k < 64; ++k) {
    const double a = (k % 2 ? 1 : -1) * 3.141592653589793 / 6;
    core::Vec to = at;
    to[0] += 5 * std::cos(a);
    to[1] += 5 * std::sin(a);
    reqs.push_back({motion::make_line(at, to), 100, false, static_cast<std::uint32_t>(k)});
    at = to;
  }
  motion::Planner planner(lim, 256);
  push_rounds(state, planner, reqs);  // the zig-zag again and again from its first point
}
BENCHMARK(BM_PlanCornersJerk);

// Planning a line-arc corner (Planner::blend_curves): 5 mm lines each followed by an R2 quarter arc
// that leaves it at 20° (a corner every push; Arg 1: jerk-limited, where the arc's tangent end onto the
// next line is blended too). Each push cuts back both pieces, fits a quintic within P (samples and a
// ternary search against the line and arc) and builds its curve and limits.
static void BM_PlanArcCorners(benchmark::State& state) {
  auto lim = xyz();
  if (state.range(0) != 0)
    for (int i : {0, 1, 2}) lim.axis[static_cast<std::size_t>(i)].j_max_mm_s3 = 10'000;
  std::vector<motion::PathRequest> reqs;
  core::Vec at{};
  double heading = 0;
  for (int k = 0; k < 32; ++k) {
    core::Vec to = at;
    to[0] += 5 * std::cos(heading);
    to[1] += 5 * std::sin(heading);
    reqs.push_back({motion::make_line(at, to), 100, false, static_cast<std::uint32_t>(2 * k)});
    at = to;
    // An arc turning left by 90°, starting 20° to the left of the line (a corner), R 2.
    const double h0 = heading + 20 * 3.141592653589793 / 180;
    core::Vec c = at;
    c[0] -= 2 * std::sin(h0);
    c[1] += 2 * std::cos(h0);
    const double a1 = std::atan2(at[1] - c[1], at[0] - c[0]) + 3.141592653589793 / 2;
    to = c;
    to[0] += 2 * std::cos(a1);
    to[1] += 2 * std::sin(a1);
    reqs.push_back({motion::make_arc(at, to, 0, 1, c[0], c[1], 1), 100, false, static_cast<std::uint32_t>(2 * k + 1)});
    at = to;
    heading = h0 + 3.141592653589793 / 2;  // the arc's end tangent: the next line goes on from it
  }
  motion::Planner planner(lim, 256);
  push_rounds(state, planner, reqs);
}
BENCHMARK(BM_PlanArcCorners)->Arg(0)->Arg(1);

// Planning fillets (jerk mode, Planner::fillet): a rounded rectangle as CAM pockets cut it, 10 and 6 mm
// lines joined by tangent R0.5 quarter arcs, P 0.05. Each arc is held and the line after it makes the
// arc and both lines' ends one quintic (the search: up to ten peak-distance scans against the two
// lines and the arc, then the arc's distance to the quintic): the costliest push of pocket.ngc.
static void BM_PlanFillets(benchmark::State& state) {
  auto lim = xyz();
  for (int i : {0, 1, 2}) lim.axis[static_cast<std::size_t>(i)].j_max_mm_s3 = 10'000;
  std::vector<motion::PathRequest> reqs;
  core::Vec at{};
  const double r = 0.5, side[2] = {10, 6};
  for (int k = 0; k < 32; ++k) {
    const double h = (k % 4) * 3.141592653589793 / 2;  // heading of the line
    const core::Vec dir{std::cos(h), std::sin(h)}, left{-std::sin(h), std::cos(h)};
    core::Vec to = at + dir * side[k % 2];
    reqs.push_back({motion::make_line(at, to), 100, false, static_cast<std::uint32_t>(2 * k), 0, 0.05});
    at = to;
    const core::Vec c = at + left * r, end = c + dir * r;
    reqs.push_back({motion::make_arc(at, end, 0, 1, c[0], c[1], 1), 100, false, static_cast<std::uint32_t>(2 * k + 1), 0, 0.05});
    at = end;
  }
  motion::Planner planner(lim, 256);
  const std::size_t pushes = push_rounds(state, planner, reqs);
  state.counters["curves_per_push"] = static_cast<double>(planner.curves_tried()) / static_cast<double>(pushes);
}
BENCHMARK(BM_PlanFillets)->Iterations(2560);  // fixed: callgrind counts compare (Planner::push ÷ 2560)

// One interpolation cycle over the blended polyline (4 axes), refilled outside the timing.
static void BM_LookaheadCycle4Axes(benchmark::State& state) {
  const auto reqs = polyline(0.05);
  motion::Planner planner(xyz(), 4096);
  motion::Interpolator in(planner.queue(), reqs.front().geom.start);
  std::size_t k = 0;
  const auto refill = [&] {
    while (!planner.queue().full()) planner.push(reqs[k++ % reqs.size()]);
  };
  refill();
  for (auto _ : state) {
    benchmark::DoNotOptimize(in.step(0.001).pos);
    if (planner.queue().size() < 1024) {
      state.PauseTiming();
      refill();
      state.ResumeTiming();
    }
  }
}
BENCHMARK(BM_LookaheadCycle4Axes);

// The jerk guard's ways to its verdict (Arg of the jerk benchmarks): 0 = simulate every brake to
// rest, 1 = simulate until the rest is π's closed-form tail, 2 = the certificate, simulating where
// it cannot decide (planner.jerk_guard_simulate = true), 3 = the certificate alone (the default).
static motion::InterpolatorConfig guard_mode(std::int64_t mode) {
  motion::InterpolatorConfig ic;
  ic.guard_closed_form = mode != 0;
  ic.guard_certificate = mode >= 2;
  ic.guard_simulate = mode <= 2;
  return ic;
}

// Steps the interpolator in jerk mode over `reqs`, pushed round and round (refilled outside the timing).
static void jerk_cycles(benchmark::State& state, const std::vector<motion::PathRequest>& reqs,
                        const motion::PlannerConfig& pc = {}) {
  auto lim = xyz();
  for (int i : {0, 1, 2, 6}) lim.axis[static_cast<std::size_t>(i)].j_max_mm_s3 = 10'000;
  motion::Planner planner(lim, 4096, pc);
  motion::Interpolator in(planner.queue(), reqs.front().geom.start, guard_mode(state.range(0)));
  std::size_t k = 0;
  const auto refill = [&] {
    while (!planner.queue().full()) planner.push(reqs[k++ % reqs.size()]);
  };
  refill();
  double v_sum = 0;
  for (auto _ : state) {
    v_sum += in.step(0.001).path_v;
    if (planner.queue().size() < 1024) {
      state.PauseTiming();
      refill();
      state.ResumeTiming();
    }
  }
  state.counters["mean_path_v_mm_s"] = v_sum / static_cast<double>(state.iterations());
  const auto cycles = static_cast<double>(std::max<std::uint64_t>(1, in.jerk_cycles()));
  state.counters["simulations_per_cycle"] = static_cast<double>(in.guard_simulations()) / cycles;
  state.counters["verifies_per_cycle"] = static_cast<double>(in.guard_verifies()) / cycles;
  // Cycles whose step a cruise certificate settled (InterpolatorConfig::guard_cruise_cycles).
  state.counters["cruise_settled"] = static_cast<double>(in.cruise_cycles_certified()) / cycles;
}

// One jerk-mode interpolation cycle (S-curve path speed with the JerkGuard's verified brake) over a
// blended CAM-like polyline (0.5 mm chords, 4 axes), jerk 10 000 mm/s³ per axis. The cycles include
// the ramps at the start, so acceleration, cruise and the brake checks at the window's end all take
// their share. Its 0.57° corners are quintics since stop 21 (PlannerConfig::g2_blend_min_rad 0.01;
// mean path speed 53 mm/s, 11.9 on the arcs before). Arg: the guard mode (guard_mode above).
static void BM_JerkCycle4Axes(benchmark::State& state) { jerk_cycles(state, polyline(0.5)); }
// A fixed number of cycles: every run covers the same stretch of the path (starting ramps, cruise,
// laps), so runs and binaries compare like for like, also under `valgrind --tool=callgrind`.
BENCHMARK(BM_JerkCycle4Axes)->DenseRange(0, 3)->Iterations(300'000);

// The same polyline with its corners blended by arcs only (what BM_JerkCycle4Axes measured until
// stop 21): lines and arcs, no Poly piece. Arg: the guard mode.
static void BM_JerkCycleArcs4Axes(benchmark::State& state) {
  motion::PlannerConfig pc;
  pc.g2_blend_min_rad = 1e9;
  jerk_cycles(state, polyline(0.5), pc);
}
BENCHMARK(BM_JerkCycleArcs4Axes)->DenseRange(0, 3)->Iterations(300'000);

// The same cycle on the same polyline smoothed as the Channel does by default on a jerk-limited
// machine (polyline_smoothing.hpp: one C² B-spline lap of Poly pieces). Arg: the guard mode.
static void BM_JerkCycleSmoothed4Axes(benchmark::State& state) {
  const auto lines = polyline(0.5);
  std::vector<core::Vec> pts{lines.front().geom.start};
  for (const auto& r : lines) pts.push_back(r.geom.end);
  std::vector<std::vector<motion::Segment>> out;
  motion::PolylineSmoothing cfg;
  cfg.threads = 1;  // not timed, but one thread is enough
  motion::smooth_polyline(pts, cfg, out);
  std::vector<motion::PathRequest> reqs;
  for (const auto& l : out)
    for (const auto& seg : l) reqs.push_back({seg, 100, false, static_cast<std::uint32_t>(reqs.size())});
  jerk_cycles(state, reqs);
}
BENCHMARK(BM_JerkCycleSmoothed4Axes)->DenseRange(0, 3)->Iterations(50'000);

// One whole cycle of a channel (Channel::update, which plans, then Interpolator::step) on 1 µm
// collinear lines at 100 mm/s: the channel runs up to kMaxInstructionsPerCycle (1024) of them a
// cycle, merged 16 to a block by the planner. Arg: 0 trapezoids, 1 jerk limits (the lines thinned
// into 50 µm legs and smoothed at load, not timed). max_cycle_us: the most CPU time one cycle took;
// max_steady_us: the same after the first 100 cycles (the first cycles fill the window, 16 blocks
// more than the path passed each, where a full window takes only what the path used up).
static void BM_ChannelCycleMicronLines(benchmark::State& state) {
  const bool jerk = state.range(0) != 0;
  motion::MachineLimits lim;
  for (int i = 0; i < 2; ++i) lim.axis[i] = {200, 2000, jerk ? 50000.0 : 0.0, -1, 1e6};
  program::Program prog;
  prog.files = {"micron.ngc"};
  constexpr int kLines = 400'000;  // 400 mm: 4 s at 100 mm/s
  for (int k = 1; k <= kLines; ++k) {
    core::Vec to{};
    to[0] = 0.001 * k;
    prog.instructions.push_back({{0, static_cast<std::uint32_t>(k), 1}, program::Linear{to, 100}});
  }
  prog.instructions.push_back({{0, kLines + 1u, 1}, program::ProgramEnd{}});
  motion::Planner planner(lim, 2000);
  motion::Interpolator interp(planner.queue(), core::Vec{});
  control::Channel ch(planner, interp);
  ch.load(prog);
  ch.start({});
  double worst = 0, steady = 0;
  int n = 0;
  for (auto _ : state) {
    timespec t0{}, t1{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t0);
    ch.update(0.001);
    interp.step(0.001);
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t1);
    const double us = 1e6 * static_cast<double>(t1.tv_sec - t0.tv_sec) + 1e-3 * static_cast<double>(t1.tv_nsec - t0.tv_nsec);
    worst = std::max(worst, us);
    if (++n > 100) steady = std::max(steady, us);
    if (ch.state() != control::ChannelState::Running) {
      state.PauseTiming();
      ch.start({});
      state.ResumeTiming();
    }
  }
  state.counters["max_cycle_us"] = worst;
  state.counters["max_steady_us"] = steady;
}
BENCHMARK(BM_ChannelCycleMicronLines)->Arg(0)->Arg(1)->Iterations(3000)->Unit(benchmark::kMicrosecond);
